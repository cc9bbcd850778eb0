#include "marsyn/core/verification/verification.hpp"

#include <atomic>
#include <mutex>

#include "marsyn/core/parallel_tasks.hpp"
#include "mpi_runs.hpp"
#include "marsyn/stopwatch.hpp"

namespace marsyn {

std::vector<Scenario> verification_scenarios(int runs, std::uint64_t seed) {
  std::vector<Scenario> out;
  out.push_back({DisturbanceMode::None, seed, 0});
  for (int v = 0; v < 4; ++v) out.push_back({DisturbanceMode::PaperConstant, seed, v});
  // The rest split evenly between constant vertices, uniform noise, vertex switching and the
  // adversary re-choosing its vertex at every integration substep.
  const DisturbanceMode cycle[4] = {DisturbanceMode::ConstantVertex, DisturbanceMode::UniformRandom,
                                    DisturbanceMode::VertexSwitching, DisturbanceMode::Adversarial};
  for (int r = static_cast<int>(out.size()); r < runs; ++r)
    out.push_back({cycle[r % 4], seed + static_cast<std::uint64_t>(r) * 2654435761ULL, 0});
  return out;
}

namespace {
std::string paper_label(int variant) {
  switch (variant) {
    case 0: return "+W, -W, +W, ... (alternating)";
    case 1: return "-W, +W, -W, ... (alternating)";
    case 2: return "+W for all agents";
    default: return "-W for all agents";
  }
}
// A kept run with its dense margins (every substep, samples included), moved out of the run (a
// copy held each kept run twice while the report was assembled).
KeptRun keep(std::string label, ClosedLoopRun&& run, SpecEvaluation spec) {
  return KeptRun{std::move(label), std::move(run.states), std::move(spec), std::move(run.dense_t),
                 std::move(run.dense_margins)};
}
KeptRun keep(const SpecMonitor& monitor, std::string label, ClosedLoopRun&& run) {
  SpecEvaluation spec = monitor.evaluate(run.states, true);
  return keep(std::move(label), std::move(run), std::move(spec));
}

// One verification run as the report counts it.
RunSummary summarize_run(const Problem& problem, bool continuous, const Scenario& scenario, const ClosedLoopRun& run) {
  const SpecEvaluation& ev = run.sampled;
  RunSummary s;
  s.scenario = scenario;
  s.between = run.between;
  s.satisfied = ev.satisfied && run.outside_domain_agent < 0;
  s.min_margin = s.sampled_margin = ev.min_margin;
  s.worst = ev.worst;
  if (continuous && run.between.min() < s.min_margin) {
    s.min_margin = run.between.min();
    s.worst = run.between_worst + " at t = " + std::to_string(run.between_worst_t) + " s (between samples)";
  }
  if (continuous && run.between.min() < 0) s.satisfied = false;
  // A tiny tolerance only for the ratio's own rounding; the tube is closed.
  s.left_tube = run.max_tube_excess > 1.0 + 1e-12;
  s.outside_domain = run.outside_domain_agent >= 0;
  if (s.outside_domain)
    s.worst = "controller of " + problem.agents[run.outside_domain_agent].name + " had no input at step " +
              std::to_string(run.outside_domain_step);
  return s;
}

// The runs' counts and smallest margins into the report; returns the worst run.
int tally(const std::vector<RunSummary>& results, VerificationReport& rep) {
  rep.runs = static_cast<int>(results.size());
  int worst_run = 0;
  for (std::size_t r = 0; r < results.size(); ++r) {
    const RunSummary& s = results[r];
    if (!s.satisfied) ++rep.violations;
    if (s.left_tube) ++rep.tube_violations;
    if (s.outside_domain) ++rep.outside_domain;
    if (s.between.min() < 0) ++rep.between_violations;
    rep.sampled_min_margin = std::min(rep.sampled_min_margin, s.sampled_margin);
    for (auto [v, part] : {std::pair{s.between.obstacle, &rep.between.obstacle},
                           std::pair{s.between.collision, &rep.between.collision},
                           std::pair{s.between.formation, &rep.between.formation},
                           std::pair{s.between.stage, &rep.between.stage}})
      if (v < *part) {
        *part = v;
        if (v <= rep.between.min()) rep.between_worst = "run " + std::to_string(r) + " (" + to_string(s.scenario.mode) + ")";
      }
    if (s.min_margin < rep.min_margin) {
      rep.min_margin = s.min_margin;
      rep.worst = s.worst + " (" + to_string(s.scenario.mode) + " disturbance, run " + std::to_string(r) + ")";
      worst_run = static_cast<int>(r);
    }
  }
  return worst_run;
}

// Open loop under the paper's constant disturbance `v`: what fails without feedback.
void add_open_loop(const SpecMonitor& monitor, int v, ClosedLoopRun&& o, VerificationReport& rep) {
  SpecEvaluation ev = monitor.evaluate(o.states, true);
  ++rep.open_loop_runs;
  if (!ev.satisfied) ++rep.open_loop_violations;
  if (ev.min_margin < rep.open_loop_min_margin) {
    rep.open_loop_min_margin = ev.min_margin;
    rep.open_loop_worst = ev.worst + " (" + paper_label(v) + ")";
  }
  OpenLoopRun run;
  run.label = paper_label(v);
  run.satisfied = ev.satisfied;
  run.goal = ev.goal_margin;
  for (int k = 0; k < static_cast<int>(ev.per_step.size()); ++k) {
    const StepMargins& m = ev.per_step[k];
    for (auto [value, part] : {std::pair{m.obstacle, &run.obstacle}, std::pair{m.collision, &run.collision},
                               std::pair{m.formation, &run.formation}})
      if (value < part->margin) *part = {value, k};
  }
  rep.open_loop.push_back(run);
  rep.kept.push_back(keep("open loop, constant disturbance " + paper_label(v), std::move(o), std::move(ev)));
}

}  // namespace

int default_verification_runs(int agents) {
  constexpr int kSmallTeam = 100, kRuns = 1000, kAgentRuns = 100'000, kFewest = 200;
  if (agents <= kSmallTeam) return kRuns;
  return std::max(kFewest, kAgentRuns / agents);
}

double verification_memory_bytes(const Problem& problem, int fine_substeps) {
  constexpr double kKeptRuns = 10;
  // Per kept run and substep, besides the product state's doubles: its vector's header and the
  // allocator's, the time and the margins (with the vectors' growth room), and a few bytes per
  // agent that the dense check keeps (fitted on the field, above, when the report still copied
  // the runs: it now takes them over, so the figure errs high).
  constexpr double kPerSubstep = 64, kPerAgent = 8;
  constexpr double kInFlight = 1 << 20;  // the runs in flight, a batch per thread (crane_vehicle: 2.05 MB in all)
  const double substeps = static_cast<double>(problem.horizon) * std::max(1, fine_substeps) + 1;
  const double agents = static_cast<double>(problem.agents.size());
  return kInFlight + kKeptRuns * substeps * (8.0 * problem.product_state_dim() + kPerAgent * agents + kPerSubstep);
}

VerificationReport verify(const Problem& problem, const std::vector<NominalTrajectory>& nominal,
                          const std::vector<std::shared_ptr<const Controller>>& controllers,
                          const VerificationOptions& opt) {
  const Stopwatch clock;
  VerificationReport rep;
  // The mission stages' visit knots at the plan's horizon (the controllers' own).
  const SpecMonitor monitor(problem, nominal.empty() ? -1 : static_cast<int>(nominal.front().u.size()));
  rep.continuous = problem.guarantee == Guarantee::Continuous;
  rep.dense_resolution_s = problem.tau / std::max(1, opt.fine_substeps);
  SimulationSetup closed{&problem, nominal, controllers, opt.fine_substeps, &monitor, false, false, opt.all_pairs};
  SimulationSetup open{&problem, nominal, {}, opt.fine_substeps, &monitor, false, true, opt.all_pairs};
  SimulationSetup closed_dense = closed, open_dense = open;
  closed_dense.keep_dense = open_dense.keep_dense = closed_dense.keep_states = true;

  // The runs kept for the report, known before the others (every rank runs them: each writes the
  // same report): the nominal (undisturbed open loop), for the reference curves, then the
  // paper's constant disturbances closed loop and open loop. They share the threads with the
  // verification runs, first, since each is longer (dense states and margins kept).
  // Batched like the others (a run in a batch is the run alone, closed_loop.hpp): the nominal
  // and three open-loop runs, the fourth open-loop run, the four closed-loop runs.
  struct Kept {
    const SimulationSetup* setup;
    std::vector<Scenario> scenarios;
    std::vector<ClosedLoopRun> runs;
  };
  auto paper = [&](int v) { return Scenario{DisturbanceMode::PaperConstant, opt.seed, v}; };
  std::vector<Kept> kept{{&open_dense, {{DisturbanceMode::None, opt.seed, 0}, paper(0), paper(1), paper(2)}, {}},
                         {&open_dense, {paper(3)}, {}},
                         {&closed_dense, {paper(0), paper(1), paper(2), paper(3)}, {}}};
  // Each is read once, at the end, and moved into the report.
  auto kept_run = [&](bool closed_loop, int v) -> ClosedLoopRun&& {  // v = -1: the nominal
    if (closed_loop) return std::move(kept[2].runs[static_cast<size_t>(v)]);
    return std::move(v < 3 ? kept[0].runs[static_cast<size_t>(v + 1)] : kept[1].runs[0]);
  };
  const int n_kept = static_cast<int>(kept.size());

  const int asked = opt.runs > 0 ? opt.runs : default_verification_runs(static_cast<int>(problem.agents.size()));
  const std::vector<Scenario> scenarios = verification_scenarios(std::max(asked, 5), opt.seed);
  std::vector<RunSummary> results(scenarios.size());
  // This rank's runs, in batches of Lanes::kWidth that advance together (closed_loop.hpp).
  std::vector<int> owned;
  for (int r = 0; r < static_cast<int>(scenarios.size()); ++r)
    if (mpi::owns_run(opt.collective, r)) owned.push_back(r);
  const int batches = (static_cast<int>(owned.size()) + Lanes::kWidth - 1) / Lanes::kWidth;
  const Stopwatch runs_clock;
  std::atomic<int> done{0};
  std::mutex progress_mutex;
  parallel_tasks(n_kept + batches, opt.threads, [&](int task) {
    if (task < n_kept) {
      Kept& k = kept[static_cast<size_t>(task)];
      k.runs = simulate(*k.setup, k.scenarios);
      return;
    }
    const int first = (task - n_kept) * Lanes::kWidth;
    const int count = std::min(Lanes::kWidth, static_cast<int>(owned.size()) - first);
    std::vector<Scenario> batch;
    for (int b = 0; b < count; ++b) batch.push_back(scenarios[owned[first + b]]);
    const std::vector<ClosedLoopRun> runs = simulate(closed, batch);
    for (int b = 0; b < count; ++b) {
      const int r = owned[first + b];
      results[r] = summarize_run(problem, rep.continuous, scenarios[r], runs[b]);
    }
    // All ranks: about as far as this one.
    const int d = (done += count) * (opt.collective ? opt.collective->size() : 1);
    if (opt.progress) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      opt.progress(std::min(d, static_cast<int>(scenarios.size())), static_cast<int>(scenarios.size()));
    }
  });
  if (opt.collective) mpi::exchange_runs(*opt.collective, results);
  rep.runs_time_s = runs_clock.seconds();

  const int worst_run = tally(results, rep);
  rep.kept.push_back(keep(monitor, "nominal (no disturbance, open loop)", kept_run(false, -1)));
  for (int v = 0; v < 4; ++v)
    rep.kept.push_back(keep(monitor, "feedback, constant disturbance " + paper_label(v), kept_run(true, v)));
  rep.kept.push_back(keep(monitor, std::string("feedback, worst run (") + to_string(scenarios[worst_run].mode) + ")",
                          simulate(closed_dense, scenarios[worst_run])));
  // Open loop under the paper's constant disturbances: what fails without feedback.
  for (int v = 0; v < 4; ++v) add_open_loop(monitor, v, kept_run(false, v), rep);
  rep.time_s = clock.seconds();
  return rep;
}

}  // namespace marsyn
