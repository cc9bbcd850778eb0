#include "marsyn/core/problem/tracker_assessment.hpp"

namespace marsyn {

std::shared_ptr<const Tracker> TrackerInstances::get(const PluginChoice& choice) {
  for (const auto& [c, t] : made_)
    if (c.name == choice.name && c.params.values() == choice.params.values()) return t;
  std::shared_ptr<const Tracker> t = registry_->create<Tracker>(choice.name, choice.params);
  made_.emplace_back(choice, t);
  return t;
}

std::vector<std::shared_ptr<const Tracker>> TrackerInstances::for_agents(const Problem& pb) {
  std::vector<std::shared_ptr<const Tracker>> out;
  for (const auto& a : pb.agents) out.push_back(get(a.tracker));
  return out;
}

namespace {
TrackerAssessment failed(const std::string& what) {
  TrackerAssessment r;
  r.ok = false;
  r.message = what;
  return r;
}
}  // namespace

TrackerAssessment assess_tracker(const Tracker& tracker, const AgentSpec& agent, const AssessRequest& request) {
  // A stated initial set binds only a tracker that says it covers one: another would verify from
  // x0 alone, and the guarantee would not hold from the starts the problem states.
  if (agent.x0_radius.size() > 0 && agent.x0_radius.maxCoeff() > 0 && !tracker.capabilities().initial_set) {
    TrackerAssessment r = failed(tracker.name() + " does not take a stated initial set (x0_radius); give x0 as a point or "
                                 "choose a tracker that does (abcd, funnel)");
    r.field = "x0_radius";
    return r;
  }
  try {
    return tracker.assess(agent, request);
  } catch (const std::exception& e) {
    return failed(std::string("the assessment failed: ") + e.what());
  }
}

TrackerAssessment assess_tracker(TrackerInstances& trackers, const PluginChoice& choice, const AgentSpec& agent,
                                 const AssessRequest& request) {
  std::shared_ptr<const Tracker> t;
  try {
    t = trackers.get(choice);
  } catch (const std::exception& e) {
    return failed(std::string("the tracker could not be created: ") + e.what());
  }
  return assess_tracker(*t, agent, request);
}

}  // namespace marsyn
