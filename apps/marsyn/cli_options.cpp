#include "cli_options.hpp"

#include <optional>

#include "commands.hpp"

namespace marsyn::cli {
namespace {

void add_export(CLI::App& app, CliOptions& o) {
  o.export_cmd = app.add_subcommand("export", "write controllers as dependency-free C99 or in SCOTS v0.2's format (docs/deploy.md)");
  o.export_cmd->add_option("CONTROLLER", o.export_inputs, "controller files (.ctrl) or folders written by `marsyn solve`")->required();
  o.export_cmd->add_option("--format", o.export_format, "c (header + source per controller) or scs (SCOTS v0.2 text)")->required();
  o.export_cmd->add_option("--out", o.export_out, "output folder (default .)");
  o.export_cmd->add_option("--prefix", o.export_prefix, "C symbol / file prefix, a C identifier (default: the agent's name)");
  o.export_cmd->add_option("--encoding", o.export_encoding, "C tables: auto (the smaller), dense (bit-packed) or rle (default auto)");
  o.export_cmd->add_option("--tracker", o.export_tracker,
                           "the tracker plugin that wrote the controllers (default: per file, the agent's tracker in the "
                           "result.json beside it, else the installed tracker that recognises the file)");
}

#ifdef MARSYN_WITH_PIPELINE
void add_plan_track_solve(CLI::App& app, CliOptions& o) {
  o.plan = app.add_subcommand("plan", "plan the eps-robust nominal trajectory of all agents (plan.json, CSVs)");
  o.plan->add_option("CONFIG", o.config, "problem file (YAML)")->required();
  o.plan->add_option("--out", o.out, "output folder (default marsyn-out/<problem name>)");

  o.track = app.add_subcommand("track", "synthesize one agent's tracking controller");
  o.track->add_option("CONFIG", o.config, "problem file (YAML)")->required();
  o.track->add_option("--agent", o.agent, "the agent's name")->required();
  o.track->add_option("--plan", o.plan_file,
                      "a plan.json from `marsyn plan`, or 'straight-line' for the geometric plan of paper Sec. 3.5 "
                      "(default: plan now)");
  o.track->add_option("--out", o.out, "output folder for <agent>.ctrl (default marsyn-out/<problem name>)");
  o.track->add_option("--threads", o.threads, "threads (default 2)")->check(CLI::Range(1, 256));

  o.solve = app.add_subcommand("solve", "plan, track every agent, verify, and write result.json, controllers, report.html");
  o.solve->add_option("CONFIG", o.config, "problem file (YAML); default: the multi-drone example");
  o.solve->add_option("--out", o.out, "output folder (default marsyn-out/<problem name>)");
  o.solve->add_option("--runs", o.runs, "closed-loop verification runs (default 1000; above 100 agents 100,000 / agents, at least 200)")->check(CLI::Range(5, 10000000));
  o.solve->add_option("--threads", o.threads, "threads (default 2)")->check(CLI::Range(1, 256));
  o.solve->add_option("--global-budget", o.global_budget,
                      "memory budget [bytes] under which the global ABCD baseline is attempted (default 2e9; 0: never)")
      ->check(CLI::Range(0.0, 1e15));
  o.time_limit_option = o.solve->add_option("--time-limit", o.time_limit,
                      "the search's budget in seconds: it plans and tracks again while a change is left and time remains "
                      "(default: the file's search: {time_limit}, else 600; docs/search.md)")
      ->check(CLI::Range(1e-3, 1e9));
  o.solve->add_option("--resume", o.resume,
                      "continue from the folder a stopped or failed solve of this problem left: its plan (when still "
                      "eps-robust) and its controllers are kept, only the other agents are tracked (docs/search.md)");
}

void add_simulate_verify(CLI::App& app, CliOptions& o) {
  o.simulate = app.add_subcommand("simulate", "replay the closed loop of all agents with their controllers");
  o.simulate->add_option("CONFIG", o.config, "problem file (YAML)")->required();
  o.simulate->add_option("--controllers", o.controllers, "a folder written by `marsyn solve`")->required();
  o.simulate->add_option("--disturbance", o.mode, "none | vertex | paper | uniform | switching (default uniform)");
  o.simulate->add_option("--seed", o.seed, "random seed (default 1)");
  o.simulate->add_option("--out", o.sim_out, "trajectory CSV (default <controllers>/simulation-<mode>.csv)");

  o.verify = app.add_subcommand("verify", "the closed-loop verification runs alone, on the controllers of a solve folder");
  o.verify->add_option("CONFIG", o.config, "problem file (YAML)")->required();
  o.verify->add_option("--controllers", o.controllers, "a folder written by `marsyn solve`")->required();
  o.verify->add_option("--plan", o.plan_file, "the nominal plan: a plan.json or 'straight-line' (default <controllers>/plan.json)");
  o.verify->add_option("--runs", o.runs, "closed-loop runs (default 1000; above 100 agents 100,000 / agents, at least 200)")->check(CLI::Range(5, 10000000));
  o.verify->add_option("--threads", o.threads, "threads (default 2)")->check(CLI::Range(1, 256));
  o.verify->add_flag("--all-pairs", o.all_pairs, "check every requirement at every substep (the broad phase's reference)");
}

void add_bench(CLI::App& app, CliOptions& o) {
  o.bench = app.add_subcommand("bench", "measure planners (or the whole method) on examples; prints a table, writes CSV and markdown");
  o.bench->add_option("--examples", o.bench_examples, "comma-separated example names or files (default: all five)");
  o.bench->add_option("--planners", o.bench_planners, "comma-separated planner plugins (default: every one installed)");
  o.bench->add_option("--stage", o.bench_stage, "plan (planners, then tracking) or solve (the whole method)")
      ->check(CLI::IsMember({"plan", "solve"}));
  o.bench->add_flag("--no-track", o.no_track, "with --stage plan: skip tracking after planning");
  o.bench->add_option("--runs", o.runs, "with --stage solve: verification runs (default 1000; above 100 agents 100,000 / agents, at least 200)")->check(CLI::Range(5, 10000000));
  o.bench->add_option("--threads", o.threads, "threads (default 2)")->check(CLI::Range(1, 256));
  o.bench->add_option("--out", o.bench_out, "folder for bench.csv and bench.md (default marsyn-out/bench)");
}
#endif

}  // namespace

void add_options(CLI::App& app, CliOptions& o) {
  // Options of the top level may also follow the subcommand (`marsyn check --memory-budget 4G x.yaml`).
  app.fallthrough();
  app.add_option("--memory-budget", o.memory_budget,
                 "memory the stages may plan to use, checked against the estimates when a problem is loaded and by the "
                 "trackers while they synthesize: bytes, or with K/M/G/T (default: half of the physical memory)");

  o.plugins = app.add_subcommand("plugins", "list every plugin found: kind, name, library");
  o.plugins->add_flag("--params", o.show_params, "also list each plugin's parameters");

  o.check = app.add_subcommand("check", "load and validate a problem file, print a summary");
  o.check->add_option("CONFIG", o.config, "problem file (YAML)")->required();

  add_export(app, o);
#ifdef MARSYN_WITH_PIPELINE
  add_plan_track_solve(app, o);
  add_simulate_verify(app, o);
  add_bench(app, o);
#endif
}

bool runs_on_every_rank(const CliOptions& o) {
  return (o.solve && *o.solve) || (o.track && *o.track);
}

int run_command(const CliOptions& o, const LoadOptions& load, const Collective* cluster) {
  if (*o.plugins) return run_plugins(o.show_params);
  if (*o.check) return run_check(o.config, load);
  if (*o.export_cmd)
    return run_export(o.export_inputs, o.export_format, o.export_out, o.export_prefix, o.export_encoding, o.export_tracker);
#ifdef MARSYN_WITH_PIPELINE
  if (*o.plan) return run_plan(o.config, o.out, load);
  if (*o.track) return run_track(o.config, o.agent, o.plan_file, o.out, o.threads, load, cluster);
  if (*o.solve)
    return run_solve(o.config.empty() ? default_example() : o.config, o.out, o.runs, o.threads, o.global_budget,
                     o.time_limit_option->count() ? std::optional<double>(o.time_limit) : std::nullopt, load, cluster, o.resume);
  if (*o.simulate) return run_simulate(o.config, o.controllers, o.mode, o.seed, o.sim_out, load);
  if (*o.verify) return run_verify(o.config, o.controllers, o.plan_file, o.runs, o.threads, o.all_pairs, load);
  if (*o.bench)
    return run_bench(o.bench_examples, o.bench_planners, o.bench_stage, !o.no_track, o.runs, o.threads, o.bench_out, load);
#else
  (void)cluster;
#endif
  return 2;
}

}  // namespace marsyn::cli
