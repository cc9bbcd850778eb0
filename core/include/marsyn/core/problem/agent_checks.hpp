#pragma once
// The per-coordinate conditions an agent's x0, eps, goal and bounds must meet for planning to
// start, whatever tracker follows: the loader rejects violations with located messages, the
// orchestrator's parameter search never proposes them. Conditions of a tracker's own (abcd: its
// grid and x0's cell) are that tracker's, asked through Tracker::assess.
#include <string>

#include "marsyn/problem.hpp"

namespace marsyn {

enum class AgentDefect {
  None,
  X0OutsideBounds,    // x0 not in X
  TubeOutsideBounds,  // x0 +- eps not in X
  InitialSetOutsideTube,  // the stated initial set x0 +- x0_radius not strictly inside x0 +- eps
  GoalEmpty,          // Goal shrunk by eps is empty
  GoalOutsideBounds,  // Goal and X do not overlap
  GoalUnreachable,    // Goal shrunk by eps and X shrunk by eps do not overlap: no eps-robust final state
  AngleTubeTooWide,   // a periodic coordinate's eps of a quarter turn or more (a reading could lie on two branches)
};

// Coordinate i is an angle the agent's dynamics turns freely in (Dynamics::periodic).
bool periodic_coordinate(const AgentSpec& agent, int i);
// An angle's tube of a quarter turn or more (AgentDefect::AngleTubeTooWide; the loader locates
// it at eps first).
bool angle_tube_too_wide(const AgentSpec& agent, int i);

// The first defect of coordinate i, in the order listed above.
AgentDefect agent_defect(const AgentSpec& agent, int i);

bool agent_consistent(const AgentSpec& agent);

// The first defect of any coordinate in words with its numbers ("eps[theta] 0.156 empties the
// goal, whose half-width there is 0.15"), or "" when the agent is consistent.
std::string agent_defect_text(const AgentSpec& agent);

}  // namespace marsyn
