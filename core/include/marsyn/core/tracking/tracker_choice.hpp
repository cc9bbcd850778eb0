#pragma once
// Which tracker follows which agent (docs/problem-format.md, "tracker"): `tracker` at the top
// level, in `defaults` or in an agent (the agent's own wins), a tracker's name or `auto` (the
// default). For `auto` the loader asks every installed tracker's assess() and takes the ok one
// with the smallest estimated work; the others that were ok stay available, cheapest first, for
// the orchestrator's fallback when the chosen one finds no controller. The resolved choice is
// AgentSpec::tracker; what was asked and answered is kept here.
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "marsyn/core/plugins/plugin_registry.hpp"
#include "marsyn/problem.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn {

inline constexpr const char* kAutoTracker = "auto";

struct AgentTrackers {
  bool automatic = false;          // chosen by `tracker: auto`
  TrackerAssessment assessment;    // the chosen tracker's answer
  std::vector<PluginChoice> fallbacks;  // auto only: the other ok trackers, cheapest first
  // Every tracker asked, in the order asked, with its answer (auto: each installed tracker).
  std::vector<std::pair<std::string, TrackerAssessment>> asked;
};

// One tracker object per distinct choice (name and parameters), created on first use. get() is
// not thread-safe: create every agent's tracker before fanning out.
class TrackerInstances {
 public:
  explicit TrackerInstances(std::shared_ptr<const PluginRegistry> registry) : registry_(std::move(registry)) {}
  std::shared_ptr<const Tracker> get(const PluginChoice& choice);
  // Each agent's tracker (AgentSpec::tracker), index for index.
  std::vector<std::shared_ptr<const Tracker>> for_agents(const Problem& problem);
  const PluginRegistry& registry() const { return *registry_; }

 private:
  std::shared_ptr<const PluginRegistry> registry_;
  std::vector<std::pair<PluginChoice, std::shared_ptr<const Tracker>>> made_;
};

// The tracker's assessment of the agent; an exception (from creating the tracker or from
// assess) becomes a refusal whose message says so, never an escape from the loader.
TrackerAssessment assess_tracker(const Tracker& tracker, const AgentSpec& agent, const AssessRequest& request);
TrackerAssessment assess_tracker(TrackerInstances& trackers, const PluginChoice& choice, const AgentSpec& agent,
                                 const AssessRequest& request);

// The tracker that wrote each agent's controller, as `marsyn solve` records it in
// `<dir>/result.json` (agents[i].name -> agents[i].tracker.name); empty when the folder has no
// readable result.json. An auto agent's fallback may differ from the loader's first choice.
std::map<std::string, std::string> recorded_trackers(const std::string& dir);

// Reads each agent's controller file `<dir>/<agent>.ctrl` with the tracker that wrote it: the
// one result.json records (recorded_trackers), else the agent's own (AgentSpec::tracker). A
// file that cannot be read throws ConfigError(file, ...) with the tracker's reason.
std::vector<std::shared_ptr<const Controller>> read_agent_controllers(const Problem& problem, TrackerInstances& trackers,
                                                                      const std::string& dir);

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
