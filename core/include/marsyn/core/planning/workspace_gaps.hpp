#pragma once
// Gaps an agent cannot pass at any horizon: two obstacles, or an obstacle and the edge of the
// agent's workspace, closer than 2 (delta + margin) in the problem's norm. A plan through such a
// gap is infeasible however long the horizon, so `check` warns about it and a failed plan names
// it instead of suggesting a longer horizon.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "marsyn/core/planning/robust_check.hpp"
#include "marsyn/problem.hpp"

namespace marsyn::planning {

struct NarrowGap {
  std::string first, second;        // obstacle names, or "the edge x = 12 of the workspace" (agents: whose)
  double width = 0.0;               // the gap's width in the problem's norm
  double needed = 0.0;              // the largest clearance (fixed + tube) among the agents it closes
  double fixed = 0.0;               // of it, the part no tube changes: 2 (delta + radius) between obstacles, delta + radius at an edge
  std::vector<std::string> agents;  // the agents it is closed to
  bool footprint = false;           // some of them have a footprint (their margin is its reach, not eps)
  int axis = -1;                    // the workspace coordinate the gap runs across (x 0, y 1, z 2); -1: slanted
  bool body = false;                // the agent it needs most for has a radius (counted with delta)
};

// Every closed gap (width > 0: overlapping obstacles form one obstacle, not a gap). The margin
// is the per-coordinate workspace margin over the agent's state bounds (for a linear workspace
// its eps in the mapped coordinates): across x between two obstacles `needed` is 2 (delta +
// margin in x), what the eps-robust plan keeps on both sides; at a workspace edge delta + 2
// margins (the tube stays inside the bounds, delta from the obstacle); a slanted gap takes the
// largest margin.
std::vector<NarrowGap> narrow_gaps(const Problem& problem);

// An agent's way in the plane: its start, its stages' centres in order (a polygon's vertex mean),
// its goal's centre, as workspace x-y points (the offset added); empty when one of them is not a
// finite point of a linear map with x and y. The points the closed-gap diagnosis and the heading's
// winding both follow.
std::vector<Eigen::Vector2d> way_points(const AgentSpec& a);

// The closed gaps some agent's way needs, each with only those agents: what `check` and a failed
// plan warn about. A gap is on an agent's way (start, stages' centres in order, goal's centre, in
// a planar linear workspace) when its shortest way around the bare obstacles, inside its
// position bounds, passes through the gap (the way grows when the gap is plugged), or when
// every gap closed to it plugged leaves no way and opening this one alone gives one. A gap between
// beds and the field's edge that no robot drives through is not a cause. Footprints, 3-D
// workspaces, gaps across z and problems past a budget of route work keep every closed gap.
// `off_the_way`, when given, receives how many closed gaps no agent needs.
std::vector<NarrowGap> gaps_on_the_way(const Problem& problem, std::size_t* off_the_way = nullptr);

// One line: "obstacles A and B leave a gap 0.62 wide (inf-norm); passing it needs 0.88
// (2 (delta + eps)): closed to drone1, drone2 at every horizon".
std::string describe(const NarrowGap& gap);

// Starts that no eps-robust plan can keep apart: the robust check reads step 0 with the tubes
// too, so two agents whose x0 are closer than delta plus both tubes' workspace margins (or an
// agent whose x0 is within delta plus its margin of an obstacle) fail at every horizon; only a
// narrower tube or other starts help. (The real specification at x0 is the loader's: an error.)
// The factor on every agent's eps that opens the gap a failed plan is pressed into: its worst
// requirement an agent against an obstacle ("obstacle o vs a"), and a gap closed to that agent
// with o on one side (narrow_gaps). The margin is taken as proportional to eps (exact for a
// linear workspace, about so for a footprint), with 5 % to spare; 1 when no such gap, at most 0
// when delta alone closes it.
double gap_eps_factor(const Problem& problem, const RobustCheck& check);

struct CrowdedStart {
  std::string first, second;  // agent names; second is "obstacle <name>" for an obstacle
  double distance = 0.0;      // between the x0 workspace points (to the obstacle), in the problem's norm
  double needed = 0.0;        // what the eps-robust requirement keeps at step 0
  // The factor on both agents' eps (all coordinates) at which step 0 is exactly robust: the
  // margin is affine in that factor (inf-norm boxes, the 2-norm's circumscribed discs), so
  // any eps x f with f below it leaves room.
  double eps_factor = 0.0;
  // A formation pair's start (distance: theirs; the tolerance the tubes leave: robust_mu).
  bool formation = false;
  double lambda = 0.0, mu = 0.0, robust_mu = 0.0;
};

// Every crowded start, worst first (at most `limit`; `total`, when given, receives the count).
std::vector<CrowdedStart> crowded_starts(const Problem& problem, std::size_t limit = 8, std::size_t* total = nullptr);

// "a12 and a13 start 0.533 apart (inf-norm); the eps-robust plan keeps 0.64 at every step, step 0
// included: no horizon can help; eps x 0.73 or less (or starts further apart) would make step 0
// eps-robust".
std::string describe(const CrowdedStart& c, const Problem& problem);

// The largest factor on every eps that leaves all starts robust (below the smallest
// CrowdedStart::eps_factor), or 1 when no start is crowded.
double start_eps_factor(const Problem& problem);

// The same per agent: the smallest factor among the crowded starts it is part of (1 when none).
// A pair's margin falls as either tube grows, so each agent narrowed by at most its own factor
// leaves every pair's step 0 robust; agents not crowded need no narrower tube.
std::vector<double> start_eps_factors(const Problem& problem);

// The larger eps of an agent's two workspace coordinates (linear map only), or -1.
double position_eps(const AgentSpec& agent);

// Two tubes can change a formation pair's distance by up to sqrt(2) (eps_i + eps_j) in position
// (each agent's larger position eps, a box's diagonal each; linear workspaces only). The factor on
// every eps that brings that to 0.7 mu for every pair, when some pair is at or above mu (a
// longer horizon cannot widen the tolerance; only narrower tubes help); 1 otherwise.
double formation_eps_factor(const Problem& problem);

}  // namespace marsyn::planning
