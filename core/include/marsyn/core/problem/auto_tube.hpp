#pragma once
// `eps: auto` and the trackers' automatic fields (abcd's `eta_x: auto`, docs/parameters.md): the
// tube derived instead of guessed. The loader gives an auto eps a first value from the agent's own
// numbers (the goal's size, the room around x0, the disturbance); the search then plans with it,
// asks the tracker's controller how wide a tube it actually keeps, and plans again with that tube
// plus a stated margin (solve.cpp, search_auto.cpp). An automatic field follows eps by its
// owner's rule (Tracker::follow_tube).
#include <string>
#include <string_view>
#include <vector>

#include "marsyn/problem.hpp"

namespace marsyn {

struct AutoTube {
  bool eps = false;
  std::vector<std::string> fields;  // the tracker-owned fields left to marsyn (abcd: eta_x, eta_u)
  std::string field_rule;           // how their owners derive them (Tracker::follow_tube)
  std::string start_cap;            // the loader's narrowing for a crowded start, as text; empty: none
  bool automatic(std::string_view field) const {
    for (const auto& f : fields)
      if (f == field) return true;
    return false;
  }
  bool any() const { return eps || !fields.empty(); }
};

// The margin an auto eps keeps over the tube the controller was seen to keep (25 %).
inline constexpr double kAutoEpsMargin = 0.25;
// An auto eps is never narrowed below this share of its first value.
inline constexpr double kAutoEpsFloor = 0.5;
// The re-plans an auto eps may ask for after a verified round.
inline constexpr int kAutoEpsIterations = 3;

// A first eps for an agent whose eps is auto: per coordinate half the goal's half-width, at most
// 0.9 of the room between x0 and the state bounds, and at least the disturbance's one-period
// push (w tau, times 2). `why` (may be null) receives the rule as text.
// A goal whose half-width is at least this share of the state bounds' half-range counts as "any
// value" in that coordinate for the first auto eps (5 % of the range, not half the goal).
inline constexpr double kAnyGoalShare = 0.9;
Eigen::VectorXd first_auto_eps(const AgentSpec& agent, double tau, std::string* why = nullptr);

// Two agents' tubes can change their workspace distance by up to sqrt(2) (eps_i + eps_j) (a
// box's diagonal each), so a formation with tolerance mu needs that below mu with room left for
// the plan: an auto eps keeps each agent's position coordinates at most this share of
// mu / (2 sqrt 2), the pair's change then at most this share of mu.
inline constexpr double kFormationEpsShare = 0.7;

// The smallest formation tolerance mu among the pairs agent `i` belongs to; infinity when none.
double formation_tolerance(const Problem& problem, int i);

// Caps the position coordinates (a linear workspace's indices) of an auto eps for a formation of
// tolerance `mu` (above). Returns whether eps changed; `why` (may be null) receives the rule.
bool cap_auto_eps_for_formation(AgentSpec& agent, double mu, std::string* why = nullptr);

}  // namespace marsyn
