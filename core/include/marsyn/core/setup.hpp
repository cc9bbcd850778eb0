#pragma once
// The one front door to the stages (OMPL's SimpleSetup is the shape): a loaded problem, the
// plugin objects made from it, and the stages of the paper's Algorithm 1 as calls. Every front
// end (the CLI's commands, bench, the Python module) and the outer search (solve.cpp) go through
// it, so "which planner, chained after which warm-start planner, under which budget; which
// tracker, falling back to which" is written once, here.
//
//   Setup setup(load_problem("examples/pendulum.yaml"));
//   const planning::PlanOutcome plan = setup.plan();
//   const FallbackTrack t = setup.track(0, plan.nominal[0], {}, log);
//   const SolveOutcome all = setup.solve(options);  // the outer search over the stages
//
// Not thread-safe: one Setup per thread of control (the stages fan out internally).
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "marsyn/core/planning/plan.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/solve.hpp"
#include "marsyn/core/tracking/global_abcd.hpp"
#include "marsyn/core/tracking/track_agents.hpp"
#include "marsyn/core/tracking/tracker_choice.hpp"
#include "marsyn/core/verification/certification.hpp"
#include "marsyn/core/verification/verification.hpp"

namespace marsyn {

class Setup {
 public:
  using Log = std::function<void(const std::string&)>;

  explicit Setup(std::shared_ptr<const LoadedProblem> loaded);
  explicit Setup(LoadedProblem&& loaded);
  // Borrows: `loaded` must outlive the Setup (solve(loaded, options) and tests).
  explicit Setup(const LoadedProblem& loaded);

  const LoadedProblem& loaded() const { return *loaded_; }
  const Problem& problem() const { return loaded_->problem; }
  // One tracker object per choice, shared by every stage of this Setup.
  TrackerInstances& trackers() { return trackers_; }

  // The planner of a choice, created on first use and kept; throws for an unknown name or bad
  // parameters.
  const Planner& planner(const PluginChoice& choice);

  // Stages 1-2: the eps-robust plan and its projection. `problem` (default: the loaded one) names
  // the planner and the warm-start planner chained before it (Problem::warm_start_planner); the
  // search passes its own copy with a changed eps, U or horizon. options.warm_start_planner is
  // set here. Never throws for an algorithmic failure (PlanOutcome::feasible).
  planning::PlanOutcome plan(planning::PlanSearchOptions options = {});
  planning::PlanOutcome plan(const Problem& problem, planning::PlanSearchOptions options);
  // The loaded problem's nominal trajectories, or std::runtime_error("planning failed: ...").
  std::vector<NominalTrajectory> nominal(planning::PlanSearchOptions options = {});

  // Stage 3 for one agent of the loaded problem, as `marsyn track` and Python's track() run it:
  // its tracker and, under `tracker: auto`, on "no controller" the other trackers that accepted it
  // (track_with_fallback). options.memory_budget_bytes is the loaded budget, the one the
  // loader's assessments judged.
  FallbackTrack track(int agent, const NominalTrajectory& nominal, TrackOptions options, const Log& log);
  // Stage 3 for every agent of `problem` (the fan-out, track_agents), within the loaded budget.
  std::vector<AgentOutcome> track(const Problem& problem, const std::vector<NominalTrajectory>& nominal,
                                  const SolveOptions& options);

  // Stage 4 (continuous time): the specification on the controllers' period enclosures.
  CertificationReport certify(const Problem& problem, const std::vector<AgentOutcome>& agents) const;
  // Stage 5: closed loops of all agents, dense in time.
  VerificationReport verify(const Problem& problem, const std::vector<NominalTrajectory>& nominal,
                            const std::vector<std::shared_ptr<const Controller>>& controllers,
                            const VerificationOptions& options) const;
  // Each agent's `<dir>/<agent>.ctrl`, read by the tracker that wrote it (read_agent_controllers).
  std::vector<std::shared_ptr<const Controller>> read_controllers(const std::string& dir);
  // The global ABCD baseline of the report (attempt_global_abcd).
  GlobalAbcdEstimate global_baseline(const Problem& problem, const SolveOptions& options, const Log& log);

  // Everything: the outer search of Remark 2 (docs/search.md, solve.cpp) over plan, track and
  // certify, then the baseline and verification. Throws only for bad input.
  SolveOutcome solve(const SolveOptions& options);

 private:
  std::shared_ptr<const LoadedProblem> loaded_;
  TrackerInstances trackers_;
  std::vector<std::pair<PluginChoice, std::shared_ptr<const Planner>>> planners_;
};

// Each agent's controller (null where it has none), in agent order.
std::vector<std::shared_ptr<const Controller>> controllers_of(const std::vector<AgentOutcome>& agents);

}  // namespace marsyn
