#include "marsyn/core/verification.hpp"

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

namespace marsyn {

std::vector<Scenario> verification_scenarios(int runs, std::uint64_t seed) {
  std::vector<Scenario> out;
  out.push_back({DisturbanceMode::None, seed, 0});
  for (int v = 0; v < 4; ++v) out.push_back({DisturbanceMode::PaperConstant, seed, v});
  // The rest split evenly between constant vertices, uniform noise and vertex switching.
  const DisturbanceMode cycle[3] = {DisturbanceMode::ConstantVertex, DisturbanceMode::UniformRandom,
                                    DisturbanceMode::VertexSwitching};
  for (int r = static_cast<int>(out.size()); r < runs; ++r)
    out.push_back({cycle[r % 3], seed + static_cast<std::uint64_t>(r) * 2654435761ULL, 0});
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
}  // namespace

VerificationReport verify(const Problem& problem, const std::vector<NominalTrajectory>& nominal,
                          const std::vector<std::shared_ptr<const Controller>>& controllers,
                          const VerificationOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  VerificationReport rep;
  const SpecMonitor monitor(problem);
  SimulationSetup closed{&problem, nominal, controllers, opt.fine_substeps};
  SimulationSetup open{&problem, nominal, {}, opt.fine_substeps};

  // The nominal (undisturbed open loop) run, for the report's reference curves.
  {
    ClosedLoopRun nom = simulate(open, {DisturbanceMode::None, opt.seed, 0});
    rep.kept.push_back({"nominal (no disturbance, open loop)", nom.states, monitor.evaluate(nom.states, true)});
  }

  const std::vector<Scenario> scenarios = verification_scenarios(std::max(opt.runs, 5), opt.seed);
  std::vector<RunSummary> results(scenarios.size());
  std::vector<ClosedLoopRun> paper_runs(4);
  std::atomic<int> next{0}, done{0};
  std::mutex progress_mutex;
  auto worker = [&] {
    for (int r = next++; r < static_cast<int>(scenarios.size()); r = next++) {
      ClosedLoopRun run = simulate(closed, scenarios[r]);
      const SpecEvaluation ev = monitor.evaluate(run.states);
      RunSummary& s = results[r];
      s.scenario = scenarios[r];
      s.satisfied = ev.satisfied && run.outside_domain_agent < 0;
      s.min_margin = ev.min_margin;
      s.worst = ev.worst;
      // A tiny tolerance only for the ratio's own rounding; the tube is closed.
      s.left_tube = run.max_tube_excess > 1.0 + 1e-12;
      s.outside_domain = run.outside_domain_agent >= 0;
      if (s.outside_domain)
        s.worst = "controller of " + problem.agents[run.outside_domain_agent].name + " had no input at step " +
                  std::to_string(run.outside_domain_step);
      if (scenarios[r].mode == DisturbanceMode::PaperConstant) paper_runs[scenarios[r].variant] = std::move(run);
      const int d = ++done;
      if (opt.progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        opt.progress(d, static_cast<int>(scenarios.size()));
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::max(1, opt.threads); ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();

  rep.runs = static_cast<int>(results.size());
  int worst_run = 0;
  for (std::size_t r = 0; r < results.size(); ++r) {
    const RunSummary& s = results[r];
    if (!s.satisfied) ++rep.violations;
    if (s.left_tube) ++rep.tube_violations;
    if (s.outside_domain) ++rep.outside_domain;
    if (s.min_margin < rep.min_margin) {
      rep.min_margin = s.min_margin;
      rep.worst = s.worst + " (" + to_string(s.scenario.mode) + " disturbance, run " + std::to_string(r) + ")";
      worst_run = static_cast<int>(r);
    }
  }
  for (int v = 0; v < 4; ++v)
    rep.kept.push_back({"feedback, constant disturbance " + paper_label(v), paper_runs[v].states,
                        monitor.evaluate(paper_runs[v].states, true)});
  {
    ClosedLoopRun w = simulate(closed, scenarios[worst_run]);
    rep.kept.push_back({std::string("feedback, worst run (") + to_string(scenarios[worst_run].mode) + ")", w.states,
                        monitor.evaluate(w.states, true)});
  }
  // Open loop under the paper's constant disturbances: what fails without feedback.
  for (int v = 0; v < 4; ++v) {
    ClosedLoopRun o = simulate(open, {DisturbanceMode::PaperConstant, opt.seed, v});
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
    rep.kept.push_back({"open loop, constant disturbance " + paper_label(v), o.states, std::move(ev)});
  }
  rep.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

}  // namespace marsyn
