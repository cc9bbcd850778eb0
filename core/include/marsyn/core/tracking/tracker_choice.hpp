#pragma once
// Stage 3's side of the tracker choice (problem/tracker_assessment.hpp makes it at load): the
// controllers each agent's tracker wrote, read back, and one agent's tracking with the `tracker:
// auto` fallback.
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "marsyn/core/problem/tracker_assessment.hpp"

namespace marsyn {

// The tracker that wrote each agent's controller, as `marsyn solve` records it in
// `<dir>/result.json` (agents[i].name -> agents[i].tracker.name); empty when the folder has no
// readable result.json. An auto agent's fallback may differ from the loader's first choice.
std::map<std::string, std::string> recorded_trackers(const std::string& dir);

// Reads each agent's controller file `<dir>/<agent>.ctrl` with the tracker that wrote it: the
// one result.json records (recorded_trackers), else the agent's own (AgentSpec::tracker). A
// file that cannot be read throws ConfigError(file, ...) with the tracker's reason. missing_ok:
// an agent without a file gets nullptr (a stopped solve's partial folder, `solve --resume`).
std::vector<std::shared_ptr<const Controller>> read_agent_controllers(const Problem& problem, TrackerInstances& trackers,
                                                                      const std::string& dir, bool missing_ok = false);

// One agent's tracking as `marsyn track` and Python's track() do it: the agent's tracker and,
// when `tracker: auto` chose it (choice->automatic) and it answers "no controller", the other
// trackers that accepted the agent, in the loader's order (cheapest first), on the same tube and
// nominal: the agent is unchanged, so the loader's assessments still hold and nothing is
// re-planned. `solve` does the same inside its search (solve.cpp), where eps may have changed.
struct FallbackTrack {
  // Declared before the result: its library holds the controller's code, so it is released last.
  std::shared_ptr<const Tracker> instance;  // the tracker whose result this is
  TrackResult result;
  std::string tracker;                      // its name
  std::vector<std::string> tried;           // every tracker run, in order
  bool automatic = false;
};
FallbackTrack track_with_fallback(TrackerInstances& trackers, const AgentSpec& agent, const AgentTrackers* choice,
                                  const TrackingProblem& problem, const TrackOptions& options,
                                  const std::function<void(const std::string&)>& log);

}  // namespace marsyn
