#pragma once
// Workspace margins: how far an agent's workspace point can move while its state stays inside
// the eps-box around the nominal state. The eps-robust spec grows every workspace constraint by
// these margins (docs/planning.md, "Margins").
#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <mutex>
#include <vector>

#include <Eigen/Core>

#include "marsyn/problem.hpp"

namespace marsyn::planning {

// Per workspace coordinate: |p(y)_c - p(x)_c| <= m[c] for all y with |y - x| <= eps.
struct WorkspaceMargin {
  double x = 0.0, y = 0.0, z = 0.0;  // z: 3-D workspaces only (0 in the plane)
  double inf() const { return std::max(x > y ? x : y, z); }
  // The plane's expression unchanged when z = 0 (bit for bit).
  double two() const { return z == 0.0 ? std::sqrt(x * x + y * y) : std::sqrt(x * x + y * y + z * z); }
};

// A sound bound at one nominal state (exact for the linear map; an interval enclosure of the
// footprint over the eps-box otherwise). Used by the exact robustness check.
WorkspaceMargin margin_at(const AgentSpec& agent, const Eigen::VectorXd& x);
WorkspaceMargin margin_at(const AgentSpec& agent, const double* x);

// Sound bounds for nominal states inside `region` (the agent's state bounds shrunk by eps): the
// region is covered by cells along the coordinates the footprint reads, and for each cell C the
// footprint's enclosure over C + eps-box is compared with its enclosure over C. The planner's
// constraints look up the cell of the current state (a piecewise-constant margin).
// Cells are evaluated lazily (a solver visits few of them); the table is safe to share between
// threads. A footprint reading more than two coordinates gets no table: at() is then the bound at
// the state itself (margin_at, the exact check's), and max() an estimate (below).
class MarginTable {
 public:
  MarginTable(const AgentSpec& agent, const Box& region, int cells_per_dim = 256);
  // The bound of x's cell. Outside the region x is clamped to it: there the state bounds are
  // violated anyway, so the planner's constraint need not be sound.
  WorkspaceMargin at(const double* x) const;
  // Evaluates every cell: a bound over the region. Without a table (pointwise), an estimate: the
  // largest bound at the region's centre, the start, the goal's centre and the centre moved to
  // each end of every coordinate the footprint reads (routes and gap warnings read it; nothing
  // sound rests on it).
  WorkspaceMargin max() const;
  bool constant() const { return split_.empty(); }

 private:
  double edge(int s, int j) const;
  WorkspaceMargin evaluate(long idx) const;

  const AgentSpec* agent_;
  std::vector<int> split_;
  int k_ = 1;
  bool pointwise_ = false;
  Eigen::VectorXd lo_, hi_;
  WorkspaceMargin linear_;
  mutable std::vector<WorkspaceMargin> cells_;
  mutable std::unique_ptr<std::atomic<bool>[]> done_;
  mutable std::mutex fill_;
};

// The largest bound of the table: one margin valid at every state of the region (an estimate for
// footprints reading more than two coordinates: MarginTable::max).
WorkspaceMargin global_margin(const AgentSpec& agent, const Box& region, int cells_per_dim = 256);

// How fast the agent's workspace point moves in a plan (per workspace coordinate, the larger of
// the two): the field's bound over its state bounds (coordinates without finite bounds: the hull
// of x0 and the goal, widened by their distance) and input bounds, by interval arithmetic (a
// footprint's Jacobian at the box centre), and with horizon_s > 0 at most twice the average speed
// from the start to the goal centre over that time, or twice `leg_speed` (a mission's fastest
// leg, fastest_leg_speed) where that is larger. An estimate that sizes the planner's clearance
// between the samples (AssemblyOptions::between_clearance), not a bound anything sound rests on:
// 0 if not finite.
double workspace_speed_bound(const AgentSpec& agent, double horizon_s = 0.0, double leg_speed = 0.0);

}  // namespace marsyn::planning
