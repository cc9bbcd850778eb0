#pragma once
// A broad phase over the pair requirements (Constraint::pair_reach): at one product state, which
// constraints of a list can have a row above zero. A pair whose two agents' workspace points are
// farther apart than its reach is satisfied whatever the rest of their states, so a solver that
// would add nothing for a satisfied row with a zero multiplier (an augmented-Lagrangian term, a
// violation) may skip it: the screen changes the cost of an evaluation, never its value.
// Agents are swept along the workspace x axis, so a team spread over the plane costs about
// N log N + (pairs within reach), not N^2. Requirements on one agent with a box outside which
// they hold (Constraint::clear_outside: obstacles) are left out while the agent's point is
// outside the box.
#include <limits>
#include <vector>

#include "marsyn/constraint.hpp"
#include "marsyn/problem.hpp"

namespace marsyn::planner_support {

class ProximityScreen {
 public:
  // `constraints` in the solver's own order; the screen's answers index into it. Disabled, it
  // finds every constraint near (a solver's switch for comparing plans).
  ProximityScreen(const Problem& problem, const std::vector<const Constraint*>& constraints, bool enabled = true);

  // True when at least one constraint of the list can be skipped somewhere.
  bool active() const { return !pairs_.empty() || !regions_.empty(); }
  // The constraints that may have a row above zero at product state x (every constraint without
  // a reach or a box, every pair within its reach, every one-agent requirement whose agent is in
  // its box), as indices into the list in increasing order: a solver visits them alone, in the
  // order it would visit the whole list.
  // One thread's buffers, kept between calls: the agents' order along x from the last call is
  // the next one's start (consecutive knots are nearly sorted already).
  struct Buffers {
    std::vector<double> px, py;
    std::vector<int> order, hits;
  };
  // With level > 0: the constraints that may have a row above -level (the near-active ones a
  // projection takes): each reach and box widened by level / Constraint::reach_decay(), and every
  // constraint without a rate kept.
  void near(const double* x, std::vector<int>& out, Buffers& buffers, double level = 0.0) const;
  void near(const double* x, std::vector<int>& out) const { near(x, out, own_); }

 private:
  struct Pair {
    int a, b;  // agents, a < b
    double reach;
    int index;  // into the constraint list
    double decay;  // Constraint::reach_decay
  };
  struct Region {
    int agent;
    double lo[2], hi[2];  // Constraint::clear_outside's box
    int index;
    double decay;
  };
  // How far beyond its reach (or box) a constraint may have a row above -level.
  static double widening(double level, double decay) {
    return level > 0 ? (decay > 0 ? level / decay * (1.0 + 1e-9) : std::numeric_limits<double>::infinity()) : 0.0;
  }
  void sweep_pairs(Buffers& b, double level) const;
  const Problem& problem_;
  std::vector<int> offsets_;         // product state offset per agent
  int size_ = 0;                     // constraints in the list
  std::vector<int> unscreened_;      // the constraints without a reach, in increasing order
  std::vector<Pair> pairs_;
  std::vector<Region> regions_;      // in list order
  std::vector<int> first_, count_;   // pairs_ sorted by (a, b): the run of agent pair a * N + b
  double widest_ = 0.0;              // the largest reach
  double slowest_ = std::numeric_limits<double>::infinity();  // the smallest reach_decay of a pair
  mutable Buffers own_;  // near(x, out)'s
};

}  // namespace marsyn::planner_support
