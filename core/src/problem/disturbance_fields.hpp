#pragma once
// An agent's `disturbance`: W as n numbers, or {base, per} growing with the magnitude of named
// states or inputs (TubeParams::w_base, w_growth; docs/problem-format.md).
#include <string>

#include "marsyn/problem.hpp"
#include "yaml_reader.hpp"

namespace marsyn::loader {

// Reads `f` into a.tube (a.dynamics and the state and input bounds already read): w_base and
// w_growth as written, and w, the constant bound every reader of w alone takes (W at its largest
// over X and U). `sn` says what a vector's length must be.
void read_disturbance(const yaml::Field& f, AgentSpec& a, const std::string& sn);

}  // namespace marsyn::loader
