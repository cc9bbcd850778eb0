#pragma once
// abcd's grid, held as the agent's fields (AgentSpec::fields, TrackingProblem::fields; the
// paper's eta_x and eta_u, written at the agent level: docs/parameters.md): abcd declares them,
// gives an automatic one its value from eps and U, and keeps the state grid no coarser than a
// narrowed tube. Core carries them by name and reads none.
#include <string>
#include <vector>

#include "marsyn/problem.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn::abcd {

inline constexpr const char* kEtaX = "eta_x";  // the state grid's cell size, one per state
inline constexpr const char* kEtaU = "eta_u";  // the input grid's spacing, one per input

// The two fields as Tracker::agent_fields declares them.
std::vector<AgentFieldSpec> grid_field_specs();

// Tracker::follow_tube for the grid. TubeChange::Set: an automatic eta_x = 2 eps / c with c cells
// per coordinate (16, fewer above 4 states so the tube stays near 2e5 cells per step), an
// automatic eta_u = the input range / k with k points per input (20, fewer above 2 inputs);
// returns that rule (empty when neither is automatic). TubeChange::Narrowed: eta_x <= eps per
// coordinate (a smaller tube keeps a grid no coarser than itself); returns "".
std::string follow_tube(AgentSpec& agent, TubeChange change);

// Tracker::field_warnings for the grid: each coordinate whose eta_x exceeds eps (no cell fits).
std::vector<std::string> grid_warnings(const AgentSpec& agent);

}  // namespace marsyn::abcd
