#pragma once
// What `marsyn check` advises before anything runs (docs/parameters.md): per agent, every
// installed tracker's assessment (cost, memory, accept or refuse and why), which one `auto` picks
// and the fallback order; warnings with numbers where a choice cannot work or will be slow.
#include <string>
#include <vector>

#include "marsyn/core/problem/problem_loader.hpp"

namespace marsyn {

struct TrackerAdvice {
  std::string tracker;
  TrackerAssessment assessment;
};

struct AgentAdvice {
  std::string agent;
  std::vector<TrackerAdvice> trackers;  // every installed tracker, in the registry's order
  std::string chosen;                   // the agent's tracker
  bool automatic = false;
  std::vector<std::string> fallbacks;   // auto: in the order the search falls back
  std::string auto_note;                // eps / eta: auto: the first values and their rule
};

struct Advice {
  std::vector<AgentAdvice> agents;
  std::vector<std::string> warnings;  // each a sentence with its numbers
};

// The estimate above which a tracker counts as slow (a minute of one core).
inline constexpr double kSlowTrackerSeconds = 60.0;

Advice advise(const LoadedProblem& loaded);
std::string to_text(const Advice& advice);

}  // namespace marsyn
