#include "marsyn/core/problem/agent_checks.hpp"

#include <algorithm>
#include <cmath>

#include "marsyn/number_text.hpp"

namespace marsyn {

bool periodic_coordinate(const AgentSpec& a, int i) {
  if (!a.dynamics) return false;
  const std::vector<bool> periodic = a.dynamics->periodic();
  return i >= 0 && i < static_cast<int>(periodic.size()) && periodic[static_cast<std::size_t>(i)];
}

bool angle_tube_too_wide(const AgentSpec& a, int i) { return periodic_coordinate(a, i) && !(a.tube.eps[i] < 0.5 * M_PI); }

AgentDefect agent_defect(const AgentSpec& a, int i) {
  const double lo = a.state_bounds.lo[i], hi = a.state_bounds.hi[i];
  if (a.x0[i] < lo || a.x0[i] > hi) return AgentDefect::X0OutsideBounds;
  if (a.x0[i] - a.tube.eps[i] < lo || a.x0[i] + a.tube.eps[i] > hi) return AgentDefect::TubeOutsideBounds;
  if (!(a.x0_half(i) < a.tube.eps[i])) return AgentDefect::InitialSetOutsideTube;
  if (a.goal.lo[i] + a.tube.eps[i] > a.goal.hi[i] - a.tube.eps[i]) return AgentDefect::GoalEmpty;
  if (a.goal.hi[i] < lo || a.goal.lo[i] > hi) return AgentDefect::GoalOutsideBounds;
  if (std::max(a.goal.lo[i], lo) + a.tube.eps[i] > std::min(a.goal.hi[i], hi) - a.tube.eps[i]) return AgentDefect::GoalUnreachable;
  if (angle_tube_too_wide(a, i)) return AgentDefect::AngleTubeTooWide;
  return AgentDefect::None;
}

bool agent_consistent(const AgentSpec& a) {
  for (int i = 0; i < a.n(); ++i)
    if (agent_defect(a, i) != AgentDefect::None) return false;
  return true;
}

std::string agent_defect_text(const AgentSpec& a) {
  const auto names = a.dynamics ? a.dynamics->state_names() : std::vector<std::string>{};
  for (int i = 0; i < a.n(); ++i) {
    const AgentDefect d = agent_defect(a, i);
    if (d == AgentDefect::None) continue;
    const std::string eps = "eps[" + (i < static_cast<int>(names.size()) ? names[i] : std::to_string(i)) + "] " +
                            number_text(a.tube.eps[i], 4);
    const double lo = a.state_bounds.lo[i], hi = a.state_bounds.hi[i];
    switch (d) {
      case AgentDefect::X0OutsideBounds: return "x0 " + number_text(a.x0[i], 4) + " is outside the state bounds";
      case AgentDefect::TubeOutsideBounds:
        return eps + " reaches past the state bounds [" + number_text(lo, 4) + ", " + number_text(hi, 4) + "] around x0 " +
               number_text(a.x0[i], 4);
      case AgentDefect::InitialSetOutsideTube:
        return eps + " is not larger than the stated initial set's half-width " + number_text(a.x0_half(i), 4) +
               " (x0_radius): the tube must hold every start";
      case AgentDefect::GoalEmpty:
        return eps + " empties the goal, whose half-width there is " +
               number_text(0.5 * (a.goal.hi[i] - a.goal.lo[i]), 4);
      case AgentDefect::GoalOutsideBounds: return "the goal lies outside the state bounds";
      case AgentDefect::GoalUnreachable:
        return eps + " leaves no point of the goal eps inside the state bounds";
      case AgentDefect::AngleTubeTooWide:
        return eps + " reaches a quarter turn (pi/2) in an angle, where a measured angle could lie on two branches of the tube";
      case AgentDefect::None: break;
    }
  }
  return "";
}

}  // namespace marsyn
