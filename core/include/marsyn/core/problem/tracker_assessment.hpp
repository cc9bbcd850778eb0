#pragma once
// Which tracker follows which agent (docs/problem-format.md, "tracker"): `tracker` at the top
// level, in `defaults` or in an agent (the agent's own wins), a tracker's name or `auto` (the
// default). For `auto` the loader asks every installed tracker's assess() and takes the ok one
// with the smallest estimated work; the others that were ok stay available, cheapest first, for
// the fallback when the chosen one finds no controller (tracking/tracker_choice.hpp). The
// resolved choice is AgentSpec::tracker; what was asked and answered is kept here. The loader
// makes this choice, so it lives with the problem stage; tracking reads it.
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

}  // namespace marsyn
