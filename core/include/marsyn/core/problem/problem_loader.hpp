#pragma once
// Loading and validating a problem file (format: docs/problem-format.md). Every rejection is a
// ConfigError naming file, line, field path and what was expected.
#include <memory>
#include <optional>
#include <string>

#include "marsyn/core/plugins/plugin_registry.hpp"
#include "marsyn/core/problem/auto_tube.hpp"
#include "marsyn/core/problem/input_limits.hpp"
#include "marsyn/core/problem/tracker_assessment.hpp"
#include "marsyn/memory_budget.hpp"
#include "marsyn/problem.hpp"

namespace marsyn {

struct LoadedProblem {
  Problem problem;
  // The registry the problem's plugins were found in (config plugin_paths first). Plugin
  // objects keep their libraries loaded on their own; the registry is kept for creating more.
  std::shared_ptr<PluginRegistry> registry;
  // Per agent (index for index): how its tracker (AgentSpec::tracker) was chosen, the chosen
  // tracker's assessment and, for `tracker: auto`, the fallbacks.
  std::vector<AgentTrackers> trackers;
  // The budget the loader judged every estimate against (LoadOptions::memory_budget); the
  // stages after it (solve, track) judge theirs against the same value.
  MemoryBudget memory_budget;
  // The plan's memory at the file's horizon: the planner's own figure (Planner::memory), else
  // core's conservative one (planner_memory); with a warm start, the larger of the two planners'.
  // The loader refused the file when it exceeds the budget.
  MemoryEstimate plan_memory;
  std::string plan_memory_source;  // whose figure: "altro's own estimate", "core's estimate for any planner (ipopt)"
  // Per agent: whether eps and which trackers' fields (abcd's grid) the file leaves to marsyn
  // (`auto`, docs/parameters.md), and the owners' rule for those fields.
  std::vector<AutoTube> auto_tube;
  // The file's `search:` block (docs/search.md); unset fields keep SolveOptions' values.
  std::optional<double> search_time_limit_s;
  // search: {planner_fallback}: when a planner the file names finds no eps-robust plan at any
  // horizon, the search tries the default planner once (docs/search.md).
  bool planner_fallback = true;
};

// What a front end asks of the loader besides the file.
struct LoadOptions {
  MemoryBudget memory_budget = machine_memory_budget();
};

LoadedProblem load_problem(const std::string& path, const LoadOptions& options = {});

// The default planner when a config names none; the default tracker is `auto` (kAutoTracker).
inline constexpr const char* kDefaultPlanner = "altro";

}  // namespace marsyn
