#pragma once
// result.json (docs/problem-format.md, "result.json"): the solve's outcome, every agent's
// tracker and statistics, certification, verification and the attempts of the search.
#include <nlohmann/json.hpp>

#include "marsyn/core/solve.hpp"

namespace marsyn {

nlohmann::json result_json(const SolveOutcome& outcome);

// What the search did to agent i's auto eps, for the summary's `auto` line and result.json: its
// narrowing notes, else the levers' changes to it ("the search's levers changed it: 4 rounds"),
// else "the first value stood".
std::string auto_search_note(const SolveOutcome& outcome, std::size_t i);

// One figure's value as JSON (a flag, a number, or one count per step).
nlohmann::json figure_json(const TrackerFigure::Value& value);

// The figures a tracker declared (TrackerStats::figures) added to `into`, by name.
void add_figures(nlohmann::json& into, const TrackerStats& stats);

}  // namespace marsyn
