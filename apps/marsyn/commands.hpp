#pragma once
// One function per subcommand. Each returns the process exit code: 0 success, 1 the problem was
// processed but the method failed (no plan, no controller), 2 bad input.
#include <optional>
#include <string>
#include <vector>

#include "marsyn/collective.hpp"
#include "marsyn/core/problem/problem_loader.hpp"

namespace marsyn::cli {

// `load`: what every command that reads a problem asks of the loader (--memory-budget).
int run_plugins(bool show_params);
int run_check(const std::string& config, const LoadOptions& load);
int run_plan(const std::string& config, const std::string& out_dir, const LoadOptions& load);
// `cluster`: the ranks of an MPI run (docs/mpi.md), nullptr alone; rank 0 prints and writes.
int run_track(const std::string& config, const std::string& agent, const std::string& plan_file,
              const std::string& out_dir, int threads, const LoadOptions& load, const Collective* cluster = nullptr);
// time_limit_s: the search's budget in seconds (--time-limit); unset: the file's
// `search: {time_limit}`, else SolveOptions' default.
int run_solve(const std::string& config, const std::string& out_dir, int runs, int threads, double global_budget,
              std::optional<double> time_limit_s, const LoadOptions& load, const Collective* cluster = nullptr,
              const std::string& resume_dir = "");

// An MPI run's failure every rank already knows of (rank 0 found the problem file bad): main
// ends normally with the exit code instead of aborting every rank.
struct QuietExit {
  int code;
};
void mark_failure_shared();
bool failure_is_shared();
int run_simulate(const std::string& config, const std::string& controllers_dir, const std::string& mode,
                 unsigned long seed, const std::string& out_file, const LoadOptions& load);
// The closed-loop verification alone, on the controllers and plan.json of a `solve` folder.
int run_verify(const std::string& config, const std::string& controllers_dir, const std::string& plan_file, int runs,
               int threads, bool all_pairs, const LoadOptions& load);
int run_bench(const std::string& examples, const std::string& planners, const std::string& stage, bool track,
              int runs, int threads, const std::string& out_dir, const LoadOptions& load);
// Exports controller files (or the *.ctrl of folders) as C99 or SCOTS v0.2 (docs/deploy.md).
int run_export(const std::vector<std::string>& inputs, const std::string& format, const std::string& out_dir,
               const std::string& prefix, const std::string& encoding, const std::string& tracker);
// The default example `solve` runs without a CONFIG: next to the sources or the installation.
std::string default_example();

}  // namespace marsyn::cli
