#pragma once
// An agent's eps, eta_x and eta_u as written: numbers, or `auto` (docs/parameters.md).
#include <string>

#include "marsyn/core/problem/auto_tube.hpp"
#include "marsyn/problem.hpp"
#include "yaml_reader.hpp"

namespace marsyn::loader {

// Reads the three fields of agent `af` (or `defaults`) into a.tube (x0, the goal, the bounds and
// w already read). An absent eps is auto, and so are then absent grids; an auto eps gets its
// first value (first_auto_eps), an auto grid its value from eps (auto_grid). `sn`, `sm`: what
// the vectors' lengths must be, for the messages.
AutoTube read_tube(const yaml::Field& af, const yaml::Field& defaults, double tau, AgentSpec& a, const std::string& sn,
                   const std::string& sm);

}  // namespace marsyn::loader
