#pragma once
// One function per subcommand. Each returns the process exit code: 0 success, 1 the problem was
// processed but the method failed (no plan, no controller), 2 bad input.
#include <string>
#include <vector>

namespace marsyn::cli {

int run_plugins(bool show_params);
int run_check(const std::string& config);
int run_plan(const std::string& config, const std::string& out_dir);
int run_track(const std::string& config, const std::string& agent, const std::string& plan_file,
              const std::string& out_dir, int threads);
int run_solve(const std::string& config, const std::string& out_dir, int runs, int threads, double global_budget);
int run_simulate(const std::string& config, const std::string& controllers_dir, const std::string& mode,
                 unsigned long seed, const std::string& out_file);
int run_bench(const std::string& examples, const std::string& planners, const std::string& stage, bool track,
              int runs, int threads, const std::string& out_dir);
// Exports controller files (or the *.ctrl of folders) as C99 or SCOTS v0.2 (docs/deploy.md).
int run_export(const std::vector<std::string>& inputs, const std::string& format, const std::string& out_dir,
               const std::string& prefix, const std::string& encoding, const std::string& tracker);
// The default example `solve` runs without a CONFIG: next to the sources or the installation.
std::string default_example();

}  // namespace marsyn::cli
