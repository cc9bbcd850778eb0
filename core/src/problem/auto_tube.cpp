#include "marsyn/core/problem/auto_tube.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "marsyn/core/problem/agent_checks.hpp"
#include "marsyn/number_text.hpp"

namespace marsyn {

Eigen::VectorXd first_auto_eps(const AgentSpec& a, double tau, std::string* why) {
  const int n = a.n();
  Eigen::VectorXd eps(n);
  std::string any;
  for (int i = 0; i < n; ++i) {
    const double goal_half = 0.5 * (a.goal.hi[i] - a.goal.lo[i]);
    const double room = std::min(a.x0[i] - a.state_bounds.lo[i], a.state_bounds.hi[i] - a.x0[i]);
    // An angle's range is at most one turn, however many turns its bounds allow.
    const double range = periodic_coordinate(a, i) ? std::min(a.state_bounds.hi[i] - a.state_bounds.lo[i], 2 * M_PI)
                                                   : a.state_bounds.hi[i] - a.state_bounds.lo[i];
    // A goal spanning 90 % of the state bounds' range or more says nothing about the tube ("any
    // heading" written as radius 3.9 within +-4 gave a heading tube of 1.95 rad): 5 % of the
    // range instead.
    const bool says_any = !std::isfinite(goal_half) || goal_half >= kAnyGoalShare * 0.5 * range;
    double e = says_any ? 0.05 * range : 0.5 * goal_half;
    if (says_any && std::isfinite(range)) {
      const auto names = a.dynamics ? a.dynamics->state_names() : std::vector<std::string>{};
      any += (any.empty() ? "" : ", ") + (i < static_cast<int>(names.size()) ? names[i] : "x" + std::to_string(i));
    }
    e = std::max({e, 2 * a.tube.w[i] * tau, 2 * a.x0_half(i)});  // a stated initial set needs room to contract
    e = std::min({e, 0.9 * room, 0.9 * goal_half});
    eps[i] = e;
  }
  if (why)
    *why = "first value: half the goal's half-width per coordinate, at least 2 w tau (and twice a stated x0_radius), at most 0.9 of the room between x0 and the state bounds" +
           (any.empty() ? std::string()
                        : "; " + any + ": the goal spans 90 % of the bounds' range or more (any value), 5 % of the range");
  return eps;
}

double formation_tolerance(const Problem& problem, int i) {
  double mu = std::numeric_limits<double>::infinity();
  for (const auto& f : problem.formation)
    if (f.i == i || f.j == i) mu = std::min(mu, f.mu);
  return mu;
}

bool cap_auto_eps_for_formation(AgentSpec& a, double mu, std::string* why) {
  if (!std::isfinite(mu) || !a.workspace.linear()) return false;
  const double cap = kFormationEpsShare * mu / (2 * std::sqrt(static_cast<double>(a.workspace.dim())));
  bool changed = false;
  for (int i : a.workspace.index)
    if (i >= 0 && i < a.tube.eps.size() && a.tube.eps[i] > cap) a.tube.eps[i] = cap, changed = true;
  if (why && changed)
    *why = "position coordinates at most " + std::to_string(static_cast<int>(100 * kFormationEpsShare)) +
           " % of mu / (2 sqrt " + std::to_string(a.workspace.dim()) + ") = " + number_text(cap, 4) + " for the formation (mu " + number_text(mu, 4) +
           "), so that the two tubes leave the plan room";
  return changed;
}

}  // namespace marsyn
