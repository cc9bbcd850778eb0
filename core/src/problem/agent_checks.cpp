#include "marsyn/core/problem/agent_checks.hpp"

#include <algorithm>

namespace marsyn {

AgentDefect agent_defect(const AgentSpec& a, int i) {
  const double lo = a.state_bounds.lo[i], hi = a.state_bounds.hi[i];
  if (a.x0[i] < lo || a.x0[i] > hi) return AgentDefect::X0OutsideBounds;
  if (a.x0[i] - a.tube.eps[i] < lo || a.x0[i] + a.tube.eps[i] > hi) return AgentDefect::TubeOutsideBounds;
  if (a.goal.lo[i] + a.tube.eps[i] > a.goal.hi[i] - a.tube.eps[i]) return AgentDefect::GoalEmpty;
  if (a.goal.hi[i] < lo || a.goal.lo[i] > hi) return AgentDefect::GoalOutsideBounds;
  if (std::max(a.goal.lo[i], lo) + a.tube.eps[i] > std::min(a.goal.hi[i], hi) - a.tube.eps[i]) return AgentDefect::GoalUnreachable;
  return AgentDefect::None;
}

bool agent_consistent(const AgentSpec& a) {
  for (int i = 0; i < a.n(); ++i)
    if (agent_defect(a, i) != AgentDefect::None) return false;
  return true;
}

}  // namespace marsyn
