#pragma once
// An agent's mission (docs/tasks.md): `stages`, the regions it visits in order before its goal,
// with their windows, dwells and team labels.
#include <vector>

#include "marsyn/problem.hpp"
#include "yaml_reader.hpp"

namespace marsyn::loader {

using yaml::Field;

// Reads and checks agent a's `stages` (a's dynamics, bounds, eps and workspace already read):
// each region non-empty when shrunk by eps and inside the state bounds, windows consistent,
// polygons only on a linear workspace map, and the whole sequence within `horizon`.
std::vector<MissionStage> read_stages(const Field& f, const AgentSpec& a, double tau, int horizon);

// A stage's region (a stage's `region`, or a named region of the top-level `regions`), checked
// for agent a: non-empty when shrunk by a's eps and inside its state bounds; polygons only on a
// linear workspace map. Fills st.box or st.polygon.
void read_stage_region(const Field& rf, const AgentSpec& a, MissionStage& st);

// The whole sequence (one step per visit, the windows and dwells, then the goal) fits `horizon`;
// else a located error at f.
void check_mission_horizon(const Field& f, const AgentSpec& a, const std::vector<MissionStage>& stages, int horizon);

// The stages' `avoid` and `avoid_after` (obstacle names; the obstacles already read): each names
// an obstacle declared with `scope: stages`, and each such obstacle is named by some stage.
void read_stage_obstacles(Problem& pb, const std::vector<Field>& stage_fields, const Field& obstacles_field);

// Team labels (rendezvous): each names stages of at least two agents, at most one per agent.
void check_teams(const Problem& pb, const std::vector<Field>& stage_fields);

}  // namespace marsyn::loader
