#pragma once
// Rank 0 plans; the other ranks receive what the later stages read of the plan: whether it is
// feasible, its horizon, each agent's nominal trajectory, the clearance it was made with, and the
// check's message (the failure text). plan.json and the report are rank 0's alone.
#include "marsyn/collective.hpp"
#include "marsyn/core/planning/plan.hpp"

namespace marsyn::mpi {

void broadcast_plan(const Collective& c, planning::PlanOutcome& plan);

}  // namespace marsyn::mpi
