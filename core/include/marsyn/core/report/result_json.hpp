#pragma once
// result.json (docs/problem-format.md, "result.json"): the solve's outcome, every agent's
// tracker and statistics, certification, verification and the attempts of the search.
#include <nlohmann/json.hpp>

#include "marsyn/core/solve.hpp"

namespace marsyn {

nlohmann::json result_json(const SolveOutcome& outcome);

}  // namespace marsyn
