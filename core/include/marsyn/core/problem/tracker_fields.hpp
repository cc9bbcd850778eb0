#pragma once
// The agent-level fields the installed trackers own (AgentSpec::fields; abcd: its grid eta_x,
// eta_u). Each tracker declares its own (Tracker::agent_fields) and keeps them in step with the
// tube (Tracker::follow_tube); core asks every installed tracker, carries the fields and reports
// them by name, and never reads a value.
#include <string>
#include <vector>

#include "marsyn/core/problem/tracker_assessment.hpp"
#include "marsyn/problem.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn {

// The fields every installed tracker declares, in the registry's order (a name once); a tracker
// that cannot be created with its defaults declares none.
std::vector<AgentFieldSpec> installed_agent_fields(TrackerInstances& trackers);

// follow_tube on every installed tracker; returns their rules for the automatic fields, joined
// by "; " (empty: none).
std::string follow_tube(TrackerInstances& trackers, AgentSpec& agent, TubeChange change);

// Every installed tracker's field_warnings on the agent, in the registry's order.
std::vector<std::string> field_warnings(TrackerInstances& trackers, const AgentSpec& agent);

}  // namespace marsyn
