#pragma once
#include <string>

#include "marsyn/core/problem/tracker_assessment.hpp"
#include "marsyn/problem.hpp"

namespace marsyn {

// Counts of the eps-robust constraints a planner will see per step (paper eq. 2 and 3).
struct ConstraintCounts {
  int obstacle = 0;   // body x obstacle (an agent has one body unless it lists `bodies`)
  int collision = 0;  // pairs of bodies of different agents
  int formation = 0;  // formation pairs (each a two-sided constraint)
  int per_step() const { return obstacle + collision + formation; }
};

ConstraintCounts count_constraints(const Problem& problem);

// A readable one-screen description of a loaded problem (what `marsyn check` prints). With the
// loader's tracker choices (LoadedProblem::trackers), each agent's line shows its tracker, how it
// was chosen and the tracker's own assessment.
std::string summarize(const Problem& problem, const std::vector<AgentTrackers>& trackers = {});

}  // namespace marsyn
