#pragma once
// plan.json both ways, in one place (as the controller files keep theirs): written by
// `marsyn plan` / `marsyn solve`, read back as each agent's nominal trajectory by `marsyn track`,
// `marsyn simulate` and the Python module. A plan that does not fit the problem (agent names,
// dimensions, lengths) is a ConfigError naming the file and the field.
#include <string>
#include <vector>

#include "marsyn/core/planning/plan.hpp"
#include "marsyn/problem.hpp"

namespace marsyn::planning {

// plan.json: problem name, horizon, tau, feasible, solver status, timings, iterations, violation,
// smallest robust margin (and where), attempts, and per agent its states, inputs and (with
// stages) the visit knots.
void write_plan_json(const std::string& path, const Problem& problem, const PlanOutcome& outcome);

// The nominal trajectories of plan.json for the problem's agents, in problem order.
std::vector<NominalTrajectory> read_plan_json(const std::string& path, const Problem& problem);

// The plan's visit knots (plan.json's per-agent "visits", the stages in order) at the plan's
// horizon; a plan without them (written before they were part of the plan) was planned at the
// initial schedule, which is returned. Knots that are no schedule of the problem's stages at that
// horizon (order, windows, dwells, teams) are a ConfigError naming the field.
MissionSchedule read_plan_visits(const std::string& path, const Problem& problem, int horizon);

// One CSV per agent, DIR/<agent>.csv: k, t, state names..., input names... (no inputs at k = T).
// Returns the files written.
std::vector<std::string> write_agent_csvs(const std::string& dir, const Problem& problem, const PlanOutcome& outcome);

}  // namespace marsyn::planning
