#pragma once
// The command line's subcommands and the values their options fill (main.cpp parses, then runs
// the one given).
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "marsyn/collective.hpp"
#include "marsyn/core/problem/problem_loader.hpp"

namespace marsyn::cli {

struct CliOptions {
  std::string memory_budget;
  bool show_params = false;
  std::string config, out, agent, plan_file, controllers, mode = "uniform", sim_out;
  int threads = 2, runs = 0;  // runs 0: the default for the team (default_verification_runs)
  double global_budget = 2e9;
  double time_limit = 0;
  std::string resume;  // solve --resume DIR
  CLI::Option* time_limit_option = nullptr;
  unsigned long seed = 1;
  std::vector<std::string> export_inputs;
  std::string export_format, export_out = ".", export_prefix, export_encoding = "auto", export_tracker;
  bool all_pairs = false;
  std::string bench_examples, bench_planners, bench_stage = "plan", bench_out = "marsyn-out/bench";
  bool no_track = false;

  // The subcommands, nullptr where this build has none.
  CLI::App *plugins = nullptr, *check = nullptr, *export_cmd = nullptr, *plan = nullptr, *track = nullptr,
           *solve = nullptr, *simulate = nullptr, *verify = nullptr, *bench = nullptr;
};

// Declares every option and subcommand on `app`, which writes into `o` as it parses.
void add_options(CLI::App& app, CliOptions& o);

// Whether the parsed subcommand shares its work over MPI ranks (solve, track).
bool runs_on_every_rank(const CliOptions& o);

// Runs the parsed subcommand: its exit code (2 when none ran).
int run_command(const CliOptions& o, const LoadOptions& load, const Collective* cluster);

}  // namespace marsyn::cli
