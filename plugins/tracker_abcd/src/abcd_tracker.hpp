#pragma once
// The default tracker: tube-local abstraction with sound growth-bound successor boxes and a
// time-indexed controller (paper Sec. 3.4).
#include <cmath>
#include <string>
#include <vector>

#include "marsyn/params.hpp"
#include "marsyn/tracker.hpp"
#include "grid_fields.hpp"
#include "synthesis.hpp"

namespace marsyn::abcd {

// Grid cells per coordinate over the state bounds (the grid's 64-bit indices stay exact).
inline constexpr double kMaxGridCellsPerCoordinate = 1099511627776.0;  // 2^40
// Order of magnitude of one core's time per (tube cell, step, grid input) of a sweep, for
// TrackerAssessment::work_s (docs/benchmarks-tracker.md: 0.35 M tube cells x 196 inputs in
// about 0.4 s for a unicycle; reuse and the prefilter make most pairs cheap).
inline constexpr double kSecondsPerStateInputPair = 1e-8;

// The grid cells holding the initial set (x0, or x0 +- a stated x0_radius) in coordinate i, as
// one interval: cells of size eta_x aligned at state_bounds.lo.
struct CellBounds {
  double lo, hi;
};
inline CellBounds x0_cell(const AgentSpec& a, const Eigen::VectorXd& eta_x, int i) {
  const double lo = a.state_bounds.lo[i], r = a.x0_half(i);
  const double first = lo + std::floor((a.x0[i] - r - lo) / eta_x[i]) * eta_x[i];
  const double last = lo + std::floor((a.x0[i] + r - lo) / eta_x[i]) * eta_x[i];
  return {first, last + eta_x[i]};
}

class AbcdTracker : public marsyn::Tracker {
 public:
  explicit AbcdTracker(const Params& p = {});
  static std::vector<ParamSpec> param_specs();

  std::string name() const override { return "abcd"; }
  TrackerCapabilities capabilities() const override { return {.reach_avoid = true, .initial_set = true}; }
  TrackResult track(const TrackingProblem& problem, const TrackOptions& options) const override;
  TrackResult reach_avoid(const ReachAvoidProblem& problem, const TrackOptions& options) const override;
  std::shared_ptr<const Controller> read_controller(const std::string& path) const override;
  // The grid's rules for one agent (docs/tracker.md, "Assessment"): eta_x and eta_u given, x0's
  // cell inside the tube, at most 2^40 cells per coordinate, tube and input storage within the
  // memory budget request.memory_budget; work_s from tube cells x steps x grid inputs.
  TrackerAssessment assess(const AgentSpec& agent, const AssessRequest& request) const override;
  // The same against the machine's default budget (machine_memory_budget()).
  TrackerAssessment assess(const AgentSpec& agent, int horizon, double tau) const override;
  // The grid, eta_x and eta_u, as the agent's fields (grid_fields.hpp).
  std::vector<AgentFieldSpec> agent_fields() const override { return grid_field_specs(); }
  std::string follow_tube(AgentSpec& agent, TubeChange change) const override { return abcd::follow_tube(agent, change); }
  std::vector<std::string> field_warnings(const AgentSpec& agent) const override { return grid_warnings(agent); }
  // Remark 2: eta_x and eta_u (its fields) times 0.75, refused (false, agent unchanged) when x0's
  // cell would no longer fit the tube or the agent has no grid.
  bool refine(AgentSpec& agent) const override;
  // The outer search's knobs (docs/search.md): "finer state grid" (eta_x x 0.75), "finer input
  // grid" (eta_u x 0.75), "more substeps" (the enclosure's substeps x 2, up to 64), each
  // offered only while it can change the agent.
  std::vector<TrackerLever> levers(const AgentSpec& agent) const override;
  bool apply_lever(const std::string& name, const TrackFailure& failure, AgentSpec& agent) const override;

  // The parameters with the run's threads, memory budget, ranks and progress: what the sweep
  // reads. Tests and benchmarks set these directly.
  Options options_for(const TrackOptions& o) const;

 private:
  Options base_;  // the parameters, as abcd_tracker.cpp declares them
};

}  // namespace marsyn::abcd
