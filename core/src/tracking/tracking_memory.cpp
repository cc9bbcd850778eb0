#include "marsyn/core/tracking/tracking_memory.hpp"

#include <algorithm>
#include <functional>

namespace marsyn {

namespace {
// Per agent beside its controller: the result's message and figures, its failure, the outcome's
// strings (a few hundred characters each, with the allocator's blocks).
constexpr double kPerAgentResult = 8 * 1024;
}  // namespace

TrackingMemory tracking_memory(const std::vector<AgentTrackers>& trackers, int threads, int assessed_horizon, int horizon) {
  const double scale = assessed_horizon > 0 && horizon > 0 ? (horizon + 1.0) / (assessed_horizon + 1.0) : 1.0;
  TrackingMemory m;
  std::vector<double> working;
  for (const AgentTrackers& t : trackers) {
    const TrackerAssessment& a = t.assessment;
    m.kept_bytes += kPerAgentResult + scale * (a.kept_bytes > 0 ? a.kept_bytes : a.memory_bytes);
    working.push_back(scale * a.memory_bytes);
  }
  // The largest syntheses may run at once, one per thread.
  const std::size_t at_once = std::min(working.size(), static_cast<std::size_t>(std::max(1, threads)));
  std::partial_sort(working.begin(), working.begin() + static_cast<long>(at_once), working.end(), std::greater<>());
  for (std::size_t i = 0; i < at_once; ++i) m.working_bytes += working[i];
  m.at_once = static_cast<int>(at_once);
  return m;
}

}  // namespace marsyn
