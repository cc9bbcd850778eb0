// Subcommands that run the method: plan, track, solve, simulate.
#include <cmath>
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <unistd.h>
#include <csignal>
#include <atomic>

#include <optional>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "marsyn/core/planning/solver_progress.hpp"
#include "marsyn/core/tracking/sweep_progress.hpp"
#include "marsyn/core/mpi/plan_broadcast.hpp"
#include "marsyn/core/verification/closed_loop.hpp"
#include "marsyn/core/verification/run_progress.hpp"
#include "marsyn/core/verification/verification.hpp"
#include "marsyn/core/problem/config_error.hpp"
#include "marsyn/core/report/result_json.hpp"
#include "marsyn/core/report/solve_outputs.hpp"
#include "marsyn/core/setup.hpp"
#include "marsyn/core/solve.hpp"
#include "marsyn/core/stage_memory.hpp"
#include "marsyn/core/report/output_folder.hpp"
#include "marsyn/core/planning/plan_io.hpp"
#include "marsyn/core/planning/plan.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/verification/spec_monitor.hpp"
#include "marsyn/number_text.hpp"
#include "marsyn/stopwatch.hpp"

namespace fs = std::filesystem;

namespace marsyn::cli {
namespace {

// SIGINT and SIGTERM during a solve (Ctrl-C, an outer `timeout`, a cluster's job limit): the
// first asks the search to stop and write what it has (status stopped); a second one ends the
// process at once, as without the handler.
std::atomic<bool> g_stop_requested{false};

extern "C" void request_stop(int sig) {
  g_stop_requested.store(true);
  std::signal(sig, SIG_DFL);
}

void stop_on_signals() {
  g_stop_requested.store(false);
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
}

const Stopwatch kStart;  // the log lines' times count from the program's start

bool g_bar_drawn = false;  // a live progress line is on the terminal: the next line first clears it

void log_line(const std::string& s) {
  const double t = kStart.seconds();
  std::fprintf(stderr, "%s[%7.2f s] %s\n", g_bar_drawn ? "\r\033[K" : "", t, s.c_str());
  g_bar_drawn = false;
}

// SolveOptions::live on a terminal: one line redrawn in place (an empty line clears it).
void live_line(const std::string& s) {
  const double t = kStart.seconds();
  if (s.empty()) std::fprintf(stderr, "\r\033[K");
  else std::fprintf(stderr, "\r\033[K[%7.2f s] %s", t, s.c_str());
  std::fflush(stderr);
  g_bar_drawn = !s.empty();
}

bool stderr_is_terminal() { return ::isatty(::fileno(stderr)) != 0; }

// "1 agent", "3 agents".
std::string count_of(std::size_t n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

std::size_t planned_rounds(const SearchReport& s) {
  std::size_t n = 0;
  for (const auto& r : s.rounds) n += r.planned;
  return n;
}

// Over MPI, rank 0 validates the problem first and tells the others: a bad file is reported
// once, by rank 0, and every rank ends with exit code 2 without MPI_Abort; only then do the
// other ranks load the same file (each needs the models).
LoadedProblem load_on_every_rank(const std::string& config, const LoadOptions& load, const Collective* cluster) {
  if (!cluster || cluster->size() <= 1) return load_problem(config, load);
  const bool root = cluster->rank() == 0;
  std::optional<LoadedProblem> lp;
  std::exception_ptr failure;
  if (root) {
    try {
      lp.emplace(load_problem(config, load));
    } catch (...) {
      failure = std::current_exception();
    }
  }
  std::vector<std::uint8_t> ok{static_cast<std::uint8_t>(failure ? 0 : 1)};
  cluster->broadcast(ok, 0);
  if (!ok.at(0)) {
    mark_failure_shared();
    if (root) std::rethrow_exception(failure);
    throw QuietExit{2};
  }
  if (!root) lp.emplace(load_problem(config, load));
  return std::move(*lp);
}

double peak_rss_mb() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss / 1024.0;  // ru_maxrss is in KiB on Linux
}

// A tracker's figure as `marsyn track` prints it: yes/no, a number, or a per-step count read as
// its first step, its fewest (and where) and its most.
std::string figure_text(const TrackerFigure::Value& value) {
  char buf[160];
  if (const auto* b = std::get_if<bool>(&value)) return *b ? "yes" : "no";
  if (const auto* v = std::get_if<long long>(&value)) return std::to_string(*v);
  if (const auto* v = std::get_if<double>(&value)) {
    std::snprintf(buf, sizeof buf, "%.4g", *v);
    return buf;
  }
  const auto& steps = std::get<std::vector<long long>>(value);
  if (steps.empty()) return "none";
  const auto fewest = std::min_element(steps.begin(), steps.end());
  std::snprintf(buf, sizeof buf, "k=0: %lld, fewest %lld (k=%td), most %lld", steps.front(), *fewest,
                fewest - steps.begin(), *std::max_element(steps.begin(), steps.end()));
  return buf;
}

std::string out_dir_for(const std::string& requested, const Problem& pb) {
  return requested.empty() ? (fs::path("marsyn-out") / pb.name).string() : requested;
}

const AgentSpec& find_agent(const Problem& pb, const std::string& name, int* index) {
  for (std::size_t i = 0; i < pb.agents.size(); ++i)
    if (pb.agents[i].name == name) {
      *index = static_cast<int>(i);
      return pb.agents[i];
    }
  std::string names;
  for (const auto& a : pb.agents) names += (names.empty() ? "" : ", ") + a.name;
  throw ConfigError(pb.source, 0, 0, "--agent", "no agent named '" + name + "'; agents: " + names);
}

// The geometric plan of paper Sec. 3.5: states on the straight line from x0 to the goal's centre,
// ignoring the dynamics (inputs at the centre of U, only a hint for the tracker's input order).
std::vector<NominalTrajectory> straight_line(const Problem& pb) {
  std::vector<NominalTrajectory> out;
  for (const auto& a : pb.agents) {
    NominalTrajectory t;
    t.agent = a.name;
    const Eigen::VectorXd goal = a.goal.center();
    for (int k = 0; k <= pb.horizon; ++k) t.x.push_back(a.x0 + (goal - a.x0) * (static_cast<double>(k) / pb.horizon));
    for (int k = 0; k < pb.horizon; ++k) t.u.push_back(a.input_bounds.center());
    out.push_back(t);
  }
  return out;
}

// The plan stage's options as every command here gives them: progress lines to stderr.
planning::PlanSearchOptions plan_options() {
  planning::PlanSearchOptions po;
  po.log = [](const std::string& s) { log_line("[plan] " + s); };
  po.progress = [p = std::make_shared<planning::SolverProgress>(log_line, stderr_is_terminal() ? live_line : planning::SolverProgress::Sink{})](
                    const PlanProgress& x) { (*p)(x); };
  return po;
}

std::vector<NominalTrajectory> nominal_for(Setup& setup, const std::string& plan_file) {
  if (plan_file == "straight-line") {
    log_line("[plan] straight line from x0 to the goal centre (ignores the dynamics, paper Sec. 3.5)");
    return straight_line(setup.problem());
  }
  if (!plan_file.empty()) return planning::read_plan_json(plan_file, setup.problem());
  log_line("[plan] no --plan given: planning first with " + setup.problem().planner.name);
  return setup.nominal(plan_options());
}

// The problem at a saved plan's visit knots (plan.json "visits", docs/tasks.md): its stages and
// staged obstacles judged where the plan was checked. The straight line (no plan file) keeps the
// initial schedule.
Problem at_plan_visits(const Problem& pb, const std::string& plan_file, const std::vector<NominalTrajectory>& nominal) {
  if (plan_file.empty() || plan_file == "straight-line" || nominal.empty()) return pb;
  if (std::all_of(pb.agents.begin(), pb.agents.end(), [](const AgentSpec& a) { return a.stages.empty(); })) return pb;
  return planning::with_visits(pb, planning::read_plan_visits(plan_file, pb, static_cast<int>(nominal.front().u.size())));
}

}  // namespace

namespace {
bool g_failure_shared = false;
}
void mark_failure_shared() { g_failure_shared = true; }
bool failure_is_shared() { return g_failure_shared; }

int run_plan(const std::string& config, const std::string& out_requested, const LoadOptions& load) {
  Setup setup(load_problem(config, load));
  const Problem& pb = setup.problem();
  // The folder before the work: an --out that cannot be a folder is a bad input, found in a
  // second, not after the plan.
  const OutputFolder folder(out_dir_for(out_requested, pb));
  // SIGINT or SIGTERM (Ctrl-C, an outer `timeout`) ends the horizon search after the solve in
  // progress; plan.json then holds the best attempt, as at the time limit.
  stop_on_signals();
  planning::PlanSearchOptions po = plan_options();
  po.stop = [] { return g_stop_requested.load(); };
  const planning::PlanOutcome out = setup.plan(std::move(po));
  // Output rule (docs/problem-format.md): plan.json always (feasible or not, with the reason);
  // the per-agent CSVs only for a feasible plan.
  const std::string plan_json = folder.path("plan.json");
  planning::write_plan_json(plan_json, pb, out);
  std::size_t csvs = 0;
  if (out.feasible) {
    for (const auto& a : pb.agents) folder.path(a.name + ".csv");  // every CSV name checked first
    csvs = planning::write_agent_csvs(folder.dir().string(), pb, out).size();
  }
  std::cout << planning::summary(pb, out);
  std::cout << "wrote " << plan_json << " and " << count_of(csvs, "CSV file") << "\n";
  return out.feasible ? 0 : 1;
}

int run_track(const std::string& config, const std::string& agent, const std::string& plan_file,
              const std::string& out_requested, int threads, const LoadOptions& load, const Collective* cluster) {
  const bool root = !cluster || cluster->rank() == 0;
  Setup setup(load_on_every_rank(config, load, cluster));
  const Problem& pb = setup.problem();
  int index = -1;
  const AgentSpec& a = find_agent(pb, agent, &index);
  if (root) (void)OutputFolder(out_dir_for(out_requested, pb));  // a bad --out fails before the synthesis
  // Over MPI: rank 0 plans (or reads the plan), the others receive the nominal trajectories.
  planning::PlanOutcome planned;
  if (root) planned.nominal = nominal_for(setup, plan_file);
  if (cluster) mpi::broadcast_plan(*cluster, planned);
  TrackOptions to;  // its memory budget: the loader's, set by the Setup
  to.threads = threads;
  to.collective = cluster;  // every rank shares this agent's sweep (docs/mpi.md)
  // SIGINT or SIGTERM ends the synthesis in progress (status "resource limit", the tracker's
  // "stopped by the run" and how far it got), not the process with nothing said. Not over MPI:
  // ranks sharing a sweep exchange every step, and a stop seen by one rank only would hang them.
  if (!cluster) {
    stop_on_signals();
    to.stop = [] { return g_stop_requested.load(); };
  }
  if (root)
    to.progress = [p = std::make_shared<SweepProgress>(a.name, log_line, stderr_is_terminal() ? live_line : SweepProgress::Sink{})](
                      int done, int total) { (*p)(done, total); };
  // The agent's tracker; under `tracker: auto`, on "no controller" the next one that accepted it.
  if (root && cluster) log_line("[track] " + a.name + " over " + std::to_string(cluster->size()) + " ranks");
  const FallbackTrack tracked =
      setup.track(index, planned.nominal[index], to, root ? log_line : std::function<void(const std::string&)>{});
  const TrackResult& r = tracked.result;
  const std::string& used = tracked.tracker;
  const bool automatic = tracked.automatic;
  if (!root) return r.status == TrackerStatus::ControllerFound ? 0 : 1;  // rank 0 reports and writes
  const auto& s = r.stats;
  std::printf("agent               %s (%s)\n", a.name.c_str(), a.dynamics_type.c_str());
  std::printf("tracker             %s%s\n", used.c_str(), automatic ? " (chosen by tracker: auto)" : "");
  std::printf("status              %s%s%s\n", to_string(r.status), r.message.empty() ? "" : ": ", r.message.c_str());
  std::printf("N_l (pairs)         %.4g\n", s.state_input_pairs);
  std::printf("boxes computed      %lld\n", s.boxes_computed);
  std::printf("abstraction time    %.3f s\n", s.abstraction_time_s);
  std::printf("synthesis time      %.3f s\n", s.synthesis_time_s);
  std::printf("peak memory         %.1f MB (tracker), %.1f MB (process)\n", s.peak_memory_bytes / 1048576.0, peak_rss_mb());
  if (r.controller)
    std::printf("period enclosures   %zu (%d per period, %.3f s): between the samples\n",
                r.controller->period_enclosures().size(), s.enclosure_substeps, s.enclosure_time_s);
  for (const auto& f : s.figures) std::printf("%-19s %s\n", f.label.c_str(), figure_text(f.value).c_str());
  const OutputFolder folder(out_dir_for(out_requested, pb));
  {
    nlohmann::json j = {{"agent", a.name}, {"status", to_string(r.status)}, {"tracker", {{"name", used}}}};
    add_figures(j, s);  // the tracker's own figures (abcd: the winning cells per step)
    std::ofstream f(folder.path(a.name + ".track.json"));
    f << j.dump() << "\n";  // one line, as before: the per-step list is long
  }
  if (r.status == TrackerStatus::ControllerFound && r.controller) {
    const std::string file = folder.path(a.name + ".ctrl");
    r.controller->write(file);
    std::printf("controller          %s\n", file.c_str());
    return 0;
  }
  return 1;
}

namespace {

// "abcd", or "abcd x9, funnel x1" when the agents' trackers differ.
std::string trackers_text(const Problem& pb) {
  std::vector<std::pair<std::string, int>> counts;
  for (const auto& a : pb.agents) {
    auto it = std::find_if(counts.begin(), counts.end(), [&](const auto& c) { return c.first == a.tracker.name; });
    if (it == counts.end()) counts.emplace_back(a.tracker.name, 1);
    else ++it->second;
  }
  std::string text;
  for (const auto& [name, count] : counts)
    text += (text.empty() ? "" : ", ") + name + (counts.size() > 1 ? " x" + std::to_string(count) : "");
  return text;
}

// The summary's status, plan, per-agent, tracking, certification and search lines.
void print_search_summary(const SolveOutcome& out) {
  std::printf("\nstatus        %s%s%s\n", out.verified ? "VERIFIED" : out.search.interrupted ? "STOPPED" : "FAILED",
              out.failure.empty() ? "" : ": ", out.failure.c_str());
  std::printf("guarantee     %s\n", out.problem.guarantee == Guarantee::Continuous
                                        ? "continuous: safe for every t in [0, T tau], between the samples too"
                                        : "sampled: safe at t = k tau only (the paper's semantics)");
  std::printf("plan          %s, T = %d, %.3g s over %s, smallest robust margin %.4g",
              out.plan.feasible ? "feasible" : "infeasible", out.plan.horizon, out.search.plan_time_s,
              count_of(planned_rounds(out.search), "planning round").c_str(), out.plan.check.min_margin);
  if (out.plan.check.continuous)
    std::printf(" (at the samples %.4g, between them %.4g)", out.plan.check.sampled_margin, out.plan.check.between_margin);
  std::printf("\n");
  for (const auto& a : out.agents)
    std::printf("  %-12s %-8s %-14s N_l %-10.3g boxes %-8lld %.3g s\n", a.name.c_str(), a.tracker.c_str(),
                a.track.message.rfind("not tracked", 0) == 0 ? "not tracked" : to_string(a.track.status),
                a.track.stats.state_input_pairs, a.track.stats.boxes_computed,
                a.track.stats.abstraction_time_s + a.track.stats.synthesis_time_s);
  std::printf("tracking      %.3g s over every round\n", out.search.track_time_s);
  if (out.certification_ran) std::printf("certification %s\n", out.certification.message.c_str());
  std::printf("search        %s\n", out.search.message().c_str());
  // Every change the search made to what the file says, per agent, with the failure it answered.
  for (const auto& r : out.search.rounds)
    for (const auto& c : grouped(r.changes, out.problem.agents.size()))
      std::printf("  %-12s %s %s -> %s (round %d%s: %s)\n", c.agent.empty() ? "(team)" : c.agent.c_str(), c.what.c_str(),
                  c.from.c_str(), c.to.c_str(), r.index, r.undone ? ", undone" : "", r.reason.c_str());
}

// What the file left to marsyn (eps and the trackers' fields: auto), the values chosen and why.
void print_auto_values(const SolveOutcome& out) {
  for (std::size_t i = 0; i < out.auto_tube.size() && i < out.problem.agents.size(); ++i) {
    const AutoTube& at = out.auto_tube[i];
    if (!at.any()) continue;
    const AgentSpec& a = out.problem.agents[i];
    auto text = [](const Eigen::VectorXd& v) { return list_text(v, "(", ")", ",", 4); };
    std::string vals = at.eps ? "eps " + text(a.tube.eps) : "";
    for (const auto& f : at.fields) vals += (vals.empty() ? "" : ", ") + f + " " + text(a.fields.value(f));
    const std::string note = auto_search_note(out, i);
    std::printf("auto          %-12s %s: %s\n", a.name.c_str(), vals.c_str(), at.eps ? note.c_str() : "from eps and U");
  }
}

void print_verification(const VerificationReport& v) {
  if (v.between.min() < 1e299)
    std::printf("verification  %d closed-loop runs, %d violations, smallest margin %.4g at the samples, %.4g between "
                "them (dense, every %.3g s)\n",
                v.runs, v.violations, v.sampled_min_margin, v.between.min(), v.dense_resolution_s);
  else  // no obstacle, collision or formation: nothing to check between the samples but the bounds
    std::printf("verification  %d closed-loop runs, %d violations, smallest margin %.4g\n", v.runs, v.violations,
                v.sampled_min_margin);
  std::printf("              %.3g s, %.0f runs/s\n", v.time_s, v.runs_per_s());
  std::printf("open loop     %d runs, %d violations, smallest margin %.4g (%s)\n", v.open_loop_runs,
              v.open_loop_violations, v.open_loop_min_margin, v.open_loop_worst.c_str());
  // Each run's parts, so that a collision shows even where a missed goal is the worst.
  for (const auto& r : v.open_loop) {
    std::string parts;
    auto add = [&](const char* name, const OpenLoopRun::Part& p) {
      if (p.step < 0) return;
      char buf[96];
      std::snprintf(buf, sizeof buf, "%s%s %.3g (step %d)", parts.empty() ? "" : ", ", name, p.margin, p.step);
      parts += buf;
    };
    add("obstacle", r.obstacle);
    add("collision", r.collision);
    add("formation", r.formation);
    char goal[64];
    std::snprintf(goal, sizeof goal, "%sgoal %.3g", parts.empty() ? "" : ", ", r.goal);
    std::printf("  %-34s %s%s\n", r.label.c_str(), (parts + goal).c_str(), r.satisfied ? "" : "  VIOLATED");
  }
}

}  // namespace

int run_solve(const std::string& config, const std::string& out_requested, int runs, int threads, double global_budget,
              std::optional<double> time_limit_s, const LoadOptions& load, const Collective* cluster,
              const std::string& resume_dir) {
  const bool root = !cluster || cluster->rank() == 0;
  Setup setup(load_on_every_rank(config, load, cluster));
  const LoadedProblem& lp = setup.loaded();
  const std::string dir = out_dir_for(out_requested, lp.problem);
  if (root) (void)OutputFolder(dir);  // an --out that cannot be a folder fails now, not after the solve
  SolveOptions so = solve_options_for(lp);
  if (time_limit_s) so.time_limit_s = *time_limit_s;  // the command line over the file
  so.verification_runs = runs;
  so.threads = threads;
  so.global_memory_budget_bytes = global_budget;
  so.cluster = cluster;
  so.resume_dir = resume_dir;
  stop_on_signals();
  so.stop = [] { return g_stop_requested.load(); };
  if (root) so.log = log_line;  // one progress stream: rank 0's
  if (root && stderr_is_terminal()) so.live = live_line;
  if (root)
    log_line("[solve] " + lp.problem.name + ": " + count_of(lp.problem.agents.size(), "agent") + ", planner " +
             lp.problem.planner.name + ", tracker " + (lp.problem.tracker.name == kAutoTracker ? "auto: " : "") +
             trackers_text(lp.problem) + (cluster ? ", " + std::to_string(cluster->size()) + " MPI ranks" : ""));
  SolveOutcome out = setup.solve(so);
  if (!root) return out.verified ? 0 : 1;  // rank 0 writes the output folder and prints the summary
  const std::vector<std::string> written = write_solve_outputs(dir, out);
  print_search_summary(out);
  print_auto_values(out);
  if (out.verification_ran) print_verification(out.verification);
  // A large team's product grid overflows a double (1e308): say so rather than print "inf".
  if (std::isfinite(out.global.state_input_pairs) && std::isfinite(out.global.memory_bytes_estimate))
    std::printf("global ABCD   N_g = %.3g state-input pairs, >= %.3g bytes: %s\n", out.global.state_input_pairs,
                out.global.memory_bytes_estimate, out.global.status.c_str());
  else if (std::isfinite(out.global.state_input_pairs))
    std::printf("global ABCD   N_g = %.3g state-input pairs, beyond 1e308 bytes: %s\n", out.global.state_input_pairs,
                out.global.status.c_str());
  else
    std::printf("global ABCD   N_g beyond 1e308 state-input pairs (the product of %zu agents' grids): %s\n",
                out.problem.agents.size(), out.global.status.c_str());
  std::printf("total         %.4g s, peak memory %.4g MB\n", out.total_time_s, peak_rss_mb());
  if (const std::string m = stage_memory_text(out.memory); !m.empty())
    std::printf("memory        added at each stage's peak: %s\n", m.c_str());
  // A team of hundreds: the first controllers, the count, and the team's files (the line listed
  // 1003 names for 1000 robots).
  constexpr std::size_t kListed = 10;
  std::string listed;
  for (std::size_t i = 0; i < written.size(); ++i) {
    if (written.size() > kListed && i >= 3 && i + 3 < written.size()) {
      if (i == 3) listed += ", ... (" + std::to_string(written.size()) + " files)";
      continue;
    }
    listed += (listed.empty() ? "" : ", ") + written[i];
  }
  std::printf("output        %s/{%s}\n", dir.c_str(), listed.c_str());
  return out.verified ? 0 : 1;
}

int run_simulate(const std::string& config, const std::string& controllers_dir, const std::string& mode_text,
                 unsigned long seed, const std::string& out_file, const LoadOptions& load) {
  Setup setup(load_problem(config, load));
  const Problem& pb = setup.problem();
  DisturbanceMode mode;
  try {
    mode = parse_disturbance_mode(mode_text);
  } catch (const std::invalid_argument& e) {
    throw ConfigError("command line", 0, 0, "--disturbance", e.what());
  }
  const std::string plan_path = (fs::path(controllers_dir) / "plan.json").string();
  const auto nominal = planning::read_plan_json(plan_path, pb);
  // Each agent's controller, read back by the tracker that wrote it.
  const std::vector<std::shared_ptr<const Controller>> ctrls = setup.read_controllers(controllers_dir);
  // The mission stages (docs/tasks.md) that the closed loop checks, at the plan's visit knots.
  const Problem judged = at_plan_visits(pb, plan_path, nominal);
  const SpecMonitor monitor(judged, nominal.empty() ? -1 : static_cast<int>(nominal.front().u.size()));
  const SimulationSetup loop{&judged, nominal, ctrls, 20, &monitor, true};
  const ClosedLoopRun run = simulate(loop, {mode, seed, 0});
  const SpecEvaluation ev = monitor.evaluate(run.states);
  const bool continuous = pb.guarantee == Guarantee::Continuous;
  const bool between_ok = run.between.min() >= 0;
  const std::string path =
      out_file.empty() ? OutputFolder(controllers_dir).path("simulation-" + mode_text + ".csv") : out_file;
  std::ofstream f(path);
  f << "k,t";
  for (const auto& a : pb.agents)
    for (const auto& s : a.dynamics->state_names()) f << "," << a.name << "." << s;
  f << "\n";
  // Dense output: every integration substep (k is the last sample at or before t).
  for (std::size_t q = 0; q < run.dense_states.size(); ++q) {
    const double t = run.dense_t[q];
    f << static_cast<long>(q / 20) << "," << t;
    for (Eigen::Index c = 0; c < run.dense_states[q].size(); ++c) f << "," << run.dense_states[q][c];
    f << "\n";
  }
  std::printf("disturbance   %s (seed %lu)\n", to_string(mode), seed);
  std::printf("guarantee     %s\n", to_string(pb.guarantee));
  std::printf("at samples    %s, smallest margin %.4g (%s)\n", ev.satisfied ? "satisfied" : "VIOLATED", ev.min_margin,
              ev.worst.c_str());
  std::printf("between       %s, smallest margin %.4g (%s at t = %.4g s; checked every %.4g s)\n",
              between_ok ? "satisfied" : "VIOLATED", run.between.min(), run.between_worst.c_str(), run.between_worst_t,
              pb.tau / 20);
  std::printf("specification %s%s\n", ev.satisfied && (between_ok || !continuous) ? "satisfied" : "VIOLATED",
              continuous ? " (continuous time)" : " (at the samples; guarantee: sampled)");
  std::printf("tube          largest deviation %.3f of eps%s\n", run.max_tube_excess,
              run.max_tube_excess <= 1.0 ? " (inside)" : " (LEFT THE TUBE)");
  if (run.outside_domain_agent >= 0)
    std::printf("controller    %s had no input at step %d\n", pb.agents[run.outside_domain_agent].name.c_str(),
                run.outside_domain_step);
  std::printf("trajectory    %s\n", path.c_str());
  return ev.satisfied && (between_ok || !continuous) && run.outside_domain_agent < 0 ? 0 : 1;
}

int run_verify(const std::string& config, const std::string& controllers_dir, const std::string& plan_file, int runs,
               int threads, bool all_pairs, const LoadOptions& load) {
  Setup setup(load_problem(config, load));
  const Problem& pb = setup.problem();
  const std::string plan_path = plan_file.empty() ? (fs::path(controllers_dir) / "plan.json").string() : plan_file;
  const auto nominal = nominal_for(setup, plan_path);
  const std::vector<std::shared_ptr<const Controller>> ctrls = setup.read_controllers(controllers_dir);
  VerificationOptions vo;
  vo.runs = runs;
  vo.threads = threads;
  vo.all_pairs = all_pairs;
  vo.progress = [p = std::make_shared<RunProgress>(log_line, stderr_is_terminal() ? live_line : RunProgress::Sink{})](
                    int done, int total) { (*p)(done, total); };
  const VerificationReport v = setup.verify(at_plan_visits(pb, plan_path, nominal), nominal, ctrls, vo);
  // Margins to the last bit: the broad phase and --all-pairs must print the same digits.
  std::printf("check         %s\n", all_pairs ? "all pairs (reference)" : "broad phase");
  // Which elementary functions the runs used: figures from machines with and without AVX2 differ.
  std::printf("integrator    RK4 every %.3g s, %d runs at once (sin, cos, exp, ...: %s)\n", v.dense_resolution_s,
              Lanes::kWidth, lanes_vector_math() ? "libmvec, AVX2" : "libm, lane by lane");
  std::printf("verification  %d closed-loop runs, %d violations, %d left the tube, %d outside the domain\n", v.runs,
              v.violations, v.tube_violations, v.outside_domain);
  std::printf("at samples    %.17g\n", v.sampled_min_margin);
  // A kind of requirement the problem does not have keeps the monitor's 1e300: "none", not a number.
  const auto margin = [](double m) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", m);
    return m >= 1e299 ? std::string("none") : std::string(buf);
  };
  std::printf("between       obstacle %s, collision %s, formation %s (every %.3g s)\n", margin(v.between.obstacle).c_str(),
              margin(v.between.collision).c_str(), margin(v.between.formation).c_str(), v.dense_resolution_s);
  std::printf("worst         %.17g: %s\n", v.min_margin, v.worst.c_str());
  std::printf("open loop     %d runs, %d violations, smallest margin %.17g\n", v.open_loop_runs, v.open_loop_violations,
              v.open_loop_min_margin);
  std::printf("time          %.3f s, closed-loop runs %.3f s (%.1f runs/s, %d threads)\n", v.time_s, v.runs_time_s,
              v.runs_per_s(), threads);
  return v.violations == 0 && v.tube_violations == 0 ? 0 : 1;
}

}  // namespace marsyn::cli
