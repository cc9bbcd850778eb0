#pragma once
// The per-coordinate conditions an agent's eps, eta and bounds must meet for planning and
// tracking to start: the loader rejects violations with located messages, the orchestrator's
// parameter search never proposes them. One definition of the tracker grid's convention: cells
// of size eta_x aligned at the state bounds' lower corner.
#include "marsyn/problem.hpp"

namespace marsyn {

enum class AgentDefect {
  None,
  X0OutsideBounds,   // x0 not in X
  TubeOutsideBounds,  // x0 +- eps not in X
  X0CellOutsideTube,  // x0's grid cell not inside [x0 - eps, x0 + eps]: the tube would start without it
  GoalEmpty,          // Goal shrunk by eps is empty
  GoalOutsideBounds,  // Goal and X do not overlap
  GoalUnreachable,    // Goal shrunk by eps and X shrunk by eps do not overlap: no eps-robust final state
};

struct CellBounds {
  double lo, hi;
};

// The grid cell containing x0 in coordinate i.
CellBounds x0_cell(const AgentSpec& agent, int i);

// The first defect of coordinate i, in the order listed above.
AgentDefect agent_defect(const AgentSpec& agent, int i);

bool agent_consistent(const AgentSpec& agent);

}  // namespace marsyn
