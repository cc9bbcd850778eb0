// The marsyn command line: parses arguments and hands over to core. Bad input of any kind ends
// here as one precise message on stderr and exit code 2; a valid problem on which the method
// fails (no plan, no controller, a violation) ends with exit code 1.
#include <CLI/CLI.hpp>

#include <cstdlib>
#include <iostream>

#include "commands.hpp"
#include "marsyn/core/problem/config_error.hpp"
#include "marsyn/core/tracking/mpi_world.hpp"
#include "marsyn/error.hpp"

int main(int argc, char** argv) {
  // MPI starts only under mpirun/srun (docs/mpi.md); otherwise a world of one, as before.
  marsyn::mpi::World world(argc, argv);
  CLI::App app{
      "marsyn: formally guaranteed, decentralized controllers for multi-agent reach-avoid problems\n"
      "(plan globally, project per agent, track locally with a sound abstraction)"};
  app.set_version_flag("--version", std::string("marsyn ") + MARSYN_VERSION + "\nMPI: " + marsyn::mpi::description());
  app.require_subcommand(1);
  // Options of the top level may also follow the subcommand (`marsyn check --memory-budget 4G x.yaml`).
  app.fallthrough();
  std::string memory_budget;
  app.add_option("--memory-budget", memory_budget,
                 "memory the stages may plan to use, checked against the estimates when a problem is loaded and by the "
                 "trackers while they synthesize: bytes, or with K/M/G/T (default: half of the physical memory)");

  bool show_params = false;
  auto* plugins = app.add_subcommand("plugins", "list every plugin found: kind, name, library");
  plugins->add_flag("--params", show_params, "also list each plugin's parameters");

  std::string config, out, agent, plan_file, controllers, mode = "uniform", sim_out;
  int threads = 2, runs = 1000;
  double global_budget = 2e9;
  double time_limit = 0;
  CLI::Option* time_limit_option = nullptr;
  unsigned long seed = 1;
  auto* check = app.add_subcommand("check", "load and validate a problem file, print a summary");
  check->add_option("CONFIG", config, "problem file (YAML)")->required();

  std::vector<std::string> export_inputs;
  std::string export_format, export_out = ".", export_prefix, export_encoding = "auto", export_tracker;
  auto* export_cmd = app.add_subcommand("export", "write controllers as dependency-free C99 or in SCOTS v0.2's format (docs/deploy.md)");
  export_cmd->add_option("CONTROLLER", export_inputs, "controller files (.ctrl) or folders written by `marsyn solve`")->required();
  export_cmd->add_option("--format", export_format, "c (header + source per controller) or scs (SCOTS v0.2 text)")->required();
  export_cmd->add_option("--out", export_out, "output folder (default .)");
  export_cmd->add_option("--prefix", export_prefix, "C symbol / file prefix, a C identifier (default: the agent's name)");
  export_cmd->add_option("--encoding", export_encoding, "C tables: auto (the smaller), dense (bit-packed) or rle (default auto)");
  export_cmd->add_option("--tracker", export_tracker,
                         "the tracker plugin that wrote the controllers (default: per file, the agent's tracker in the "
                         "result.json beside it, else abcd)");

#ifdef MARSYN_WITH_PIPELINE
  auto* plan = app.add_subcommand("plan", "plan the eps-robust nominal trajectory of all agents (plan.json, CSVs)");
  plan->add_option("CONFIG", config, "problem file (YAML)")->required();
  plan->add_option("--out", out, "output folder (default marsyn-out/<problem name>)");

  auto* track = app.add_subcommand("track", "synthesize one agent's tracking controller");
  track->add_option("CONFIG", config, "problem file (YAML)")->required();
  track->add_option("--agent", agent, "the agent's name")->required();
  track->add_option("--plan", plan_file,
                    "a plan.json from `marsyn plan`, or 'straight-line' for the geometric plan of paper Sec. 3.5 "
                    "(default: plan now)");
  track->add_option("--out", out, "output folder for <agent>.ctrl (default marsyn-out/<problem name>)");
  track->add_option("--threads", threads, "threads (default 2)")->check(CLI::Range(1, 256));

  auto* solve = app.add_subcommand("solve", "plan, track every agent, verify, and write result.json, controllers, report.html");
  solve->add_option("CONFIG", config, "problem file (YAML); default: the multi-drone example");
  solve->add_option("--out", out, "output folder (default marsyn-out/<problem name>)");
  solve->add_option("--runs", runs, "closed-loop verification runs (default 1000)")->check(CLI::Range(5, 10000000));
  solve->add_option("--threads", threads, "threads (default 2)")->check(CLI::Range(1, 256));
  solve->add_option("--global-budget", global_budget,
                    "memory budget [bytes] under which the global ABCD baseline is attempted (default 2e9; 0: never)")
      ->check(CLI::Range(0.0, 1e15));
  time_limit_option = solve->add_option("--time-limit", time_limit,
                    "the search's budget in seconds: it plans and tracks again while a change is left and time remains "
                    "(default: the file's search: {time_limit}, else 600; docs/search.md)")
      ->check(CLI::Range(1e-3, 1e9));

  auto* simulate = app.add_subcommand("simulate", "replay the closed loop of all agents with their controllers");
  simulate->add_option("CONFIG", config, "problem file (YAML)")->required();
  simulate->add_option("--controllers", controllers, "a folder written by `marsyn solve`")->required();
  simulate->add_option("--disturbance", mode, "none | vertex | paper | uniform | switching (default uniform)");
  simulate->add_option("--seed", seed, "random seed (default 1)");
  simulate->add_option("--out", sim_out, "trajectory CSV (default <controllers>/simulation-<mode>.csv)");

  bool all_pairs = false;
  auto* verify = app.add_subcommand("verify", "the closed-loop verification runs alone, on the controllers of a solve folder");
  verify->add_option("CONFIG", config, "problem file (YAML)")->required();
  verify->add_option("--controllers", controllers, "a folder written by `marsyn solve`")->required();
  verify->add_option("--plan", plan_file, "the nominal plan: a plan.json or 'straight-line' (default <controllers>/plan.json)");
  verify->add_option("--runs", runs, "closed-loop runs (default 1000)")->check(CLI::Range(5, 10000000));
  verify->add_option("--threads", threads, "threads (default 2)")->check(CLI::Range(1, 256));
  verify->add_flag("--all-pairs", all_pairs, "check every requirement at every substep (the broad phase's reference)");

  std::string bench_examples, bench_planners, bench_stage = "plan", bench_out = "marsyn-out/bench";
  bool no_track = false;
  auto* bench = app.add_subcommand("bench", "measure planners (or the whole method) on examples; prints a table, writes CSV and markdown");
  bench->add_option("--examples", bench_examples, "comma-separated example names or files (default: all five)");
  bench->add_option("--planners", bench_planners, "comma-separated planner plugins (default: every one installed)");
  bench->add_option("--stage", bench_stage, "plan (planners, then tracking) or solve (the whole method)")
      ->check(CLI::IsMember({"plan", "solve"}));
  bench->add_flag("--no-track", no_track, "with --stage plan: skip tracking after planning");
  bench->add_option("--runs", runs, "with --stage solve: verification runs (default 1000)")->check(CLI::Range(5, 10000000));
  bench->add_option("--threads", threads, "threads (default 2)")->check(CLI::Range(1, 256));
  bench->add_option("--out", bench_out, "folder for bench.csv and bench.md (default marsyn-out/bench)");
#endif

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Every rank parses the same arguments: rank 0 alone says what is wrong.
    const int code = world.root() ? app.exit(e) : (e.get_exit_code() == 0 ? 0 : 2);
    return code == 0 ? 0 : 2;
  }
  const marsyn::Collective* cluster = world.collective();
  // Over MPI, solve and track share the work; any other subcommand is rank 0's alone.
  if (cluster && !world.root()
#ifdef MARSYN_WITH_PIPELINE
      && !*solve && !*track
#endif
  )
    return 0;
  // An error in an MPI run: said once, by the rank that had it, and the whole run ends at once
  // (MPI_Abort), never a hang; unless every rank already knows (a bad problem file).
  auto fail = [&](const std::string& message, int code) {
    if (!cluster || marsyn::cli::failure_is_shared()) {
      if (world.root()) std::cerr << message << "\n";
      return code;
    }
    std::cerr << "marsyn (rank " << world.rank() << " of " << world.size() << "): " << message << "\n";
    world.abort(code);
  };

  // One budget for the run, handed to the loader and from there to every stage.
  marsyn::LoadOptions load;
  if (!memory_budget.empty()) {
    const std::optional<double> bytes = marsyn::parse_bytes(memory_budget);
    if (!bytes)
      return fail("--memory-budget: expected a positive number of bytes such as 8e9 or 8G, got '" + memory_budget + "'",
                  2);
    load.memory_budget = {*bytes, "--memory-budget"};
  }

  try {
    if (*plugins) return marsyn::cli::run_plugins(show_params);
    if (*check) return marsyn::cli::run_check(config, load);
    if (*export_cmd)
      return marsyn::cli::run_export(export_inputs, export_format, export_out, export_prefix, export_encoding, export_tracker);
#ifdef MARSYN_WITH_PIPELINE
    if (*plan) return marsyn::cli::run_plan(config, out, load);
    if (*track) return marsyn::cli::run_track(config, agent, plan_file, out, threads, load, cluster);
    if (*solve)
      return marsyn::cli::run_solve(config.empty() ? marsyn::cli::default_example() : config, out, runs, threads, global_budget,
                                    time_limit_option->count() ? std::optional<double>(time_limit) : std::nullopt, load,
                                    cluster);
    if (*simulate) return marsyn::cli::run_simulate(config, controllers, mode, seed, sim_out, load);
    if (*verify) return marsyn::cli::run_verify(config, controllers, plan_file, runs, threads, all_pairs, load);
    if (*bench)
      return marsyn::cli::run_bench(bench_examples, bench_planners, bench_stage, !no_track, runs, threads, bench_out, load);
#endif
  } catch (const marsyn::cli::QuietExit& e) {
    return e.code;
  } catch (const marsyn::ConfigError& e) {
    return fail(std::string("error: ") + e.what(), 2);
  } catch (const marsyn::ParamError& e) {
    return fail("error: parameter " + marsyn::printable(e.field()) + ": " + marsyn::printable(e.what()), 2);
  } catch (const std::exception& e) {
    return fail("error: " + marsyn::printable(e.what()), 1);
  }
  return 2;
}
