#pragma once
// A broad phase over the pair requirements (Constraint::pair_reach): at one product state, which
// constraints of a list can have a row above zero. A pair whose two agents' workspace points are
// farther apart than its reach is satisfied whatever the rest of their states, so a solver that
// would add nothing for a satisfied row with a zero multiplier (an augmented-Lagrangian term, a
// violation) may skip it: the screen changes the cost of an evaluation, never its value.
// Agents are swept along the workspace x axis, so a team spread over the plane costs about
// N log N + (pairs within reach), not N^2.
#include <vector>

#include "marsyn/constraint.hpp"
#include "marsyn/problem.hpp"

namespace marsyn::planner_support {

class ProximityScreen {
 public:
  // `constraints` in the solver's own order; the screen's answers index into it. Disabled, it
  // marks every constraint near (a solver's switch for comparing plans).
  ProximityScreen(const Problem& problem, const std::vector<const Constraint*>& constraints, bool enabled = true);

  // True when at least one constraint of the list can be skipped somewhere.
  bool active() const { return !pairs_.empty(); }
  // near[i] = 1 when constraint i may have a row above zero at product state x (every
  // constraint without a reach, and every pair within its reach), 0 otherwise.
  void mark(const double* x, std::vector<char>& near) const;
  // The same for concurrent callers: each thread brings its own buffers.
  struct Buffers {
    std::vector<double> px, py;
    std::vector<int> order;
  };
  void mark(const double* x, std::vector<char>& near, Buffers& buffers) const;

 private:
  struct Pair {
    int a, b;  // agents, a < b
    double reach;
    int index;  // into the constraint list
  };
  const Problem& problem_;
  std::vector<int> offsets_;         // product state offset per agent
  std::vector<char> unscreened_;     // per constraint: 1 when it has no reach
  std::vector<Pair> pairs_;
  std::vector<int> first_, count_;   // pairs_ sorted by (a, b): the run of agent pair a * N + b
  double widest_ = 0.0;              // the largest reach
  mutable Buffers own_;  // the single-threaded mark's
};

}  // namespace marsyn::planner_support
