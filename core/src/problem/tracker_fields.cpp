#include "marsyn/core/problem/tracker_fields.hpp"

#include <algorithm>

namespace marsyn {

namespace {

// Every installed tracker with its defaults; one that cannot be created is left out (its
// assessment reports why when an agent asks for it).
std::vector<std::shared_ptr<const Tracker>> installed(TrackerInstances& trackers) {
  std::vector<std::shared_ptr<const Tracker>> out;
  for (const auto& name : trackers.registry().names(PluginKind<Tracker>::name)) {
    try {
      out.push_back(trackers.get({name, {}}));
    } catch (const std::exception&) {
    }
  }
  return out;
}

}  // namespace

std::vector<AgentFieldSpec> installed_agent_fields(TrackerInstances& trackers) {
  std::vector<AgentFieldSpec> out;
  for (const auto& t : installed(trackers))
    for (auto& f : t->agent_fields())
      if (std::none_of(out.begin(), out.end(), [&](const AgentFieldSpec& o) { return o.name == f.name; }))
        out.push_back(std::move(f));
  return out;
}

std::string follow_tube(TrackerInstances& trackers, AgentSpec& agent, TubeChange change) {
  std::string rules;
  for (const auto& t : installed(trackers))
    if (const std::string r = t->follow_tube(agent, change); !r.empty()) rules += (rules.empty() ? "" : "; ") + r;
  return rules;
}

std::vector<std::string> field_warnings(TrackerInstances& trackers, const AgentSpec& agent) {
  std::vector<std::string> out;
  for (const auto& t : installed(trackers))
    for (auto& w : t->field_warnings(agent)) out.push_back(std::move(w));
  return out;
}

}  // namespace marsyn
