#pragma once
// Reading a plan.json written by `marsyn plan` / `marsyn solve` back as nominal trajectories for
// a problem. A plan that does not fit the problem (agent names, dimensions, lengths) is a
// ConfigError naming the file and the field.
#include <string>
#include <vector>

#include "marsyn/problem.hpp"

namespace marsyn {

std::vector<NominalTrajectory> read_plan_json(const std::string& path, const Problem& problem);

}  // namespace marsyn
