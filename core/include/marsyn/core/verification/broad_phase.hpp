#pragma once
// The dense check's broad phase (issue 24): at every integration substep of a closed-loop run,
// the agents' workspace points sorted along x (insertion sort from the previous substep's order,
// about linear since the points move little), so that the pairs that could still lower a running
// minimum and each agent's nearest neighbour are found without visiting all N^2 pairs.
//
// Soundness of the skipping (docs/soundness.md does not rest on it: the verifier only refutes):
// a requirement is skipped only when a lower bound of its margin, minus a slack far above the
// rounding of the margin's formula, is strictly above the running minimum of its part. A skipped
// requirement can therefore neither lower nor tie the minimum, and the minima, the step where
// they fall and the requirement named there are bit for bit those of the all-pairs check
// (SpecMonitor::step), which tests/core/broad_phase_test.cpp compares.
#include <span>
#include <vector>

#include <Eigen/Core>

#include "marsyn/core/planning/spec_margins.hpp"
#include "marsyn/core/verification/spec_monitor.hpp"
#include "marsyn/problem.hpp"

namespace marsyn {

// Nearest point of a convex polygon's boundary to p (the adversary's target on an obstacle).
Eigen::Vector2d nearest_on_polygon(const planning::Polygon& poly, const Eigen::Vector2d& p);
// Its 3-D counterpart on an obstacle's prism (p's own z where the prism is unbounded in z).
planning::Point nearest_on_obstacle(const Obstacle& obstacle, const planning::Point& p);

// The adversary's target for agent i by a search over every obstacle, then every agent (strictly
// nearer only): the reference BroadPhase::nearest_target must agree with.
bool nearest_by_search(const Problem& pb, int i, const std::vector<planning::Point>& pts, planning::Point& target);

class BroadPhase {
 public:
  explicit BroadPhase(const Problem& problem);
  // The agents' points at the current substep (problem order); kept by reference until the next call.
  void update(const std::vector<planning::Point>& points);
  // running = min(running, SpecMonitor::step at the points) part by part. Returns true when the
  // smallest of the parts fell; *worst is then the requirement step() would name.
  // `when` (k >= 0) applies the staged obstacles' windows set by windows(), as step() does.
  bool accumulate(StepMargins& running, planning::Requirement* worst, planning::Moment when = {-1, false}) const;
  // A window of consecutive states at one moment (between two samples), states[s] the agents'
  // points at state s < count (kept by reference until the next call): the requirements that
  // could lower `running` at some state of the window are listed once, from each agent's bounding
  // box over the window (a planar formation pair's from the box of its difference, which the
  // states give); accumulate_window(s, ...) is then accumulate() at state s over those
  // only. A requirement is left out only when its lower bound over the boxes clears the running
  // minimum by the slack; the minima only fall, so it could not lower or tie them at any state.
  void window(const std::vector<std::vector<planning::Point>>& states, int count, const StepMargins& running,
              planning::Moment when);
  // The same with each agent's box over the window's states given (x_lo, y_lo, x_hi, y_hi, every
  // state's point inside; found where the states were written), finite false unless every
  // coordinate of every state is finite.
  void window(const std::vector<std::vector<planning::Point>>& states, std::span<const Eigen::Vector4d> boxes,
              bool finite, const StepMargins& running, planning::Moment when);
  bool accumulate_window(int s, StepMargins& running, planning::Requirement* worst) const;
  // The staged obstacles' windows (SpecMonitor::windows(), kept by pointer); none: all bind.
  void windows(const planning::ObstacleWindows* w) { windows_ = w; }
  // The adversary's target for agent i: the nearest obstacle boundary point, or the nearest other
  // agent when strictly nearer (pairwise collision on); ties as a scan in index order breaks
  // them (nearest_by_search's answer). False when there is neither. The nearest agent is found
  // first, so that an obstacle whose bounding box is farther is not searched.
  bool nearest_target(int i, planning::Point& target) const;

 private:
  // Where a requirement stands in planning::for_each_requirement's order (step()'s tie-break).
  long rank(const planning::Requirement& q) const;
  // accumulate()'s rules at one state: obstacle o cannot lower run.obstacle at an agent's point
  // `at`; a pair farther apart than pair_reach(run) along x or y cannot lower run.collision.
  bool obstacle_clears(const StepMargins& run, int i, int o, const planning::Point& at) const;
  double pair_reach(const StepMargins& run) const;
  // window()'s candidates from boxes_.
  void window_from_boxes(const std::vector<std::vector<planning::Point>>& states, int count, bool finite,
                         const StepMargins& run, planning::Moment when);
  // q's margin at the points p folded into its part `slot`; (best, best_rank) is the smallest
  // (margin, rank) so far below the minimum the state started from, and *worst its requirement.
  void fold_one(const planning::Requirement& q, const std::vector<planning::Point>& p, double& slot, double& best,
                long& best_rank, planning::Requirement* worst) const;
  const Problem& pb_;
  const std::vector<planning::Point>* pts_ = nullptr;
  const planning::ObstacleWindows* windows_ = nullptr;
  std::vector<Eigen::Vector4d> bbox_;  // per obstacle: x_lo, y_lo, x_hi, y_hi
  // Per obstacle that is not an axis-aligned box (its bounding box bounds little near a slanted
  // edge): each edge's outward unit normal n, n . a for a vertex a on it, and 1 / |n|_1, rows
  // plane_start_[o] .. plane_start_[o + 1]. The polygon is convex, so a point is at least
  // max over edges (n . p - n . a) from it in the 2-norm, that times 1 / |n|_1 in the inf-norm
  // (the distance to the edge's half-plane), when that is positive.
  std::vector<Eigen::Vector4d> planes_;
  std::vector<int> plane_start_;
  // That bound at the point (x, y), and over an axis-aligned box (x_lo, y_lo, x_hi, y_hi): the
  // distance of its every point. <= 0: no bound (inside some edge's half-plane, or a box obstacle).
  double plane_gap(int o, double x, double y, bool inf) const;
  double plane_gap(int o, const Eigen::Vector4d& box, bool inf) const;
  bool slanted(int o) const { return plane_start_[static_cast<size_t>(o)] < plane_start_[static_cast<size_t>(o) + 1]; }
  double scale_ = 0;                   // largest obstacle coordinate: the slack's scale
  // Every pair's clearance is at most this (the two largest radii): one reach for the sweep.
  double pair_clear_ = 0;
  mutable std::vector<int> order_;     // agents by increasing x (when sorted_)
  mutable std::vector<int> place_;     // place_[i]: agent i's position in order_
  mutable bool sorted_ = false;
  void sort() const;                   // order_ and place_ for the current points
  bool finite_ = true;                 // else every pair is visited (NaN cannot be sorted)
  // nearest_target(): the sorted sweep for agent i from its last answer (last_nearest_), and the
  // agents' lists: per agent, every agent within radius_ along x and y of it at the anchor
  // positions (list_[list_start_[i] .. list_start_[i + 1])), moved_ the farthest any agent has
  // moved from its anchor since, mag_ the anchors' largest coordinate (the slack's scale).
  void sweep_nearest(int i, double& ad, int& bj) const;
  void build_lists() const;
  // The last answer's two candidates first (ad < 0 when decided without the distance, e2 then its
  // sum of squares: nearest_target computes the distance where an obstacle needs it), the list
  // where they cannot decide.
  bool nearest_from_candidates(int i, double& ad, double& e2, int& bj) const;
  bool nearest_from_list(int i, double& ad, int& bj) const;
  mutable std::vector<int> last_nearest_;
  mutable std::vector<double> box2_;  // nearest_target(): each obstacle box's squared distance
  mutable std::vector<planning::Point> anchor_;
  mutable std::vector<double> radius_;
  mutable std::vector<int> list_start_, list_;
  // nearest_from_list()'s last decided answer per agent (-1: none since the lists were built), the
  // list's next nearest agent then (-1: none), and a lower bound of every other list agent's
  // distance then, less twice moved_ then. Two candidates, since neighbours placed symmetrically
  // (a circle swap) are nearly tied: which of the two is nearer is then decided afresh at each
  // state, and only a third agent's approach sends the agent back to its list.
  mutable std::vector<int> answer_, second_;
  mutable std::vector<double> others_;
  mutable double moved_ = 0, mag_ = 0;
  mutable bool lists_ready_ = false, stale_ = false;
  // window(): the states, each agent's box over them (x_lo, y_lo, x_hi, y_hi), the agents by
  // increasing x_lo, and the requirements left to fold.
  const std::vector<std::vector<planning::Point>>* window_ = nullptr;
  std::vector<Eigen::Vector4d> boxes_;
  std::vector<int> box_order_;
  std::vector<planning::Requirement> candidates_;
  std::vector<int> formation_candidates_;  // the formation pairs left to fold (their indices, in order)
};

}  // namespace marsyn
