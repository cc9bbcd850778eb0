#pragma once
// The tracking stage's memory, predicted before any plan (`marsyn check`, the solve's memory
// line): every agent keeps its controller until the run ends, and each worker thread holds one
// synthesis's working memory at a time. The trackers state both (TrackerAssessment::kept_bytes,
// memory_bytes); core adds what it keeps per agent beside the controller.
#include <vector>

#include "marsyn/core/problem/tracker_assessment.hpp"

namespace marsyn {

struct TrackingMemory {
  double kept_bytes = 0;     // every agent's controller and result
  double working_bytes = 0;  // the largest syntheses, one per thread
  int at_once = 0;           // syntheses counted in working_bytes: min(agents, threads)
  double bytes() const { return kept_bytes + working_bytes; }
};

// trackers: each agent's chosen tracker and assessment (LoadedProblem::trackers), assessed at
// `assessed_horizon` steps; the figure is for `horizon` steps (the kept controllers grow with it).
TrackingMemory tracking_memory(const std::vector<AgentTrackers>& trackers, int threads, int assessed_horizon, int horizon);

}  // namespace marsyn
