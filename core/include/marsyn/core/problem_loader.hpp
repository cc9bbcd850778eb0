#pragma once
// Loading and validating a problem file (format: docs/problem-format.md). Every rejection is a
// ConfigError naming file, line, field path and what was expected.
#include <memory>
#include <string>

#include "marsyn/core/plugin_registry.hpp"
#include "marsyn/problem.hpp"

namespace marsyn {

struct LoadedProblem {
  Problem problem;
  // The registry the problem's plugins were found in (config plugin_paths first). Plugin
  // objects keep their libraries loaded on their own; the registry is kept for creating more.
  std::shared_ptr<PluginRegistry> registry;
};

LoadedProblem load_problem(const std::string& path);

// The default planner and tracker when a config names none.
inline constexpr const char* kDefaultPlanner = "altro";
inline constexpr const char* kDefaultTracker = "abcd";

}  // namespace marsyn
