#pragma once
// An agent's eps and the trackers' own fields (abcd's eta_x, eta_u) as written: numbers, or
// `auto` (docs/parameters.md).
#include <string>
#include <vector>

#include "marsyn/core/problem/auto_tube.hpp"
#include "marsyn/core/problem/tracker_assessment.hpp"
#include "marsyn/problem.hpp"
#include "yaml_reader.hpp"

namespace marsyn::loader {

// Reads eps and the installed trackers' `fields` of agent `af` (or `defaults`) into a.tube and
// a.fields (x0, the goal, the bounds and w already read). An absent eps is auto, and so are then
// absent fields; an auto eps gets its first value (first_auto_eps), an automatic field its value
// from its owner (Tracker::follow_tube). `sn`, `sm`: what the vectors' lengths must be, for the
// messages.
AutoTube read_tube(const yaml::Field& af, const yaml::Field& defaults, double tau, AgentSpec& a, const std::string& sn,
                   const std::string& sm, const std::vector<AgentFieldSpec>& fields, TrackerInstances& trackers);

}  // namespace marsyn::loader
