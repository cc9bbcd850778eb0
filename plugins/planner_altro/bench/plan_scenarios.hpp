#pragma once
// The five examples (the same numbers as examples/*.yaml, built in code so the benchmark does not
// depend on the loader) and the 50-unicycle antipodal swap. Choices: docs/benchmarks-altro.md.
#include <string>
#include <vector>

#include "marsyn/problem.hpp"

namespace marsyn::bench {

struct Scenario {
  std::string name;
  Problem problem;
  Params planner_params;  // overrides of the altro defaults, if any
};

std::vector<std::string> scenario_names();
Scenario make_scenario(const std::string& name);  // throws std::invalid_argument for unknown names

}  // namespace marsyn::bench
