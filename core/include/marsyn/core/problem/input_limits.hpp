#pragma once
// Limits on what a problem file may ask for, checked by the loader before any stage allocates
// (docs/problem-format.md, "Checks"): names that become file names, hard bounds on counts, and
// the planning stage's memory estimate against the run's budget (LoadOptions::memory_budget).
#include <cstddef>
#include <string>

#include "marsyn/memory_budget.hpp"
#include "marsyn/problem.hpp"

namespace marsyn {

// Agent, obstacle and problem names: 1..kMaxNameLength characters from [A-Za-z0-9_.-], not
// starting with a dot. They become file names (<agent>.ctrl, marsyn-out/<problem>/).
inline constexpr std::size_t kMaxNameLength = 64;
// Empty when `name` is valid, otherwise what is wrong with it (for a located message).
std::string name_defect(const std::string& name);
// A valid name made from a file's stem (the default problem name): other characters become '_'.
std::string name_from_stem(const std::string& stem);

inline constexpr long kMaxHorizon = 100000;      // steps
inline constexpr long kMaxRk4Substeps = 1000;    // per step
inline constexpr std::size_t kMaxAgents = 1000;

struct MemoryEstimate {
  double bytes = 0;
  std::string detail;  // how the figure is made up, for the message
};

// The planner's storage for the product system over horizon T: per step the agents' dynamics
// and feedback blocks, and one constraint row per obstacle-agent and agent pair (a lower
// estimate of what the in-tree planners hold; the horizon search may lengthen T further).
MemoryEstimate planner_memory(const Problem& problem);
// Trackers estimate their own storage in Tracker::assess (abcd: plugins/tracker_abcd).

}  // namespace marsyn
