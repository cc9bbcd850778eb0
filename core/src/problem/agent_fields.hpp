#pragma once
// One agent's block: fields with their `defaults`, boxes, the workspace map, the consistency of
// x0 and the goal, and the agent's tracker resolved by the trackers' own assessments.
#include <string>

#include "marsyn/core/problem/tracker_assessment.hpp"
#include "marsyn/problem.hpp"
#include "yaml_reader.hpp"

namespace marsyn::loader {

using yaml::Field;

// An agent's field comes from its own block or, when absent there, from `defaults`.
Field agent_field(const Field& agent, const Field& defaults, const std::string& key);
Field agent_required(const Field& agent, const Field& defaults, const std::string& key);

Box read_box(const Field& f, int n, const std::string& why);
Workspace read_workspace(const Field& f, const Dynamics& dyn);
// bounds_clearance: what the body's clearance pulled the workspace coordinates' bounds in by.
void validate_agent(const AgentSpec& a, const Field& x0f, const Field& radiusf, const Field& goalf,
                    double bounds_clearance = 0.0);

// The vector field at x0 and at the goal's centre, with the input at U's centre: a division by
// zero or a log of a negative number there would otherwise send every planner and enclosure to
// inf or NaN and the search into rounds that cannot help. Located at the equation of the first
// coordinate that is not finite when the model is written as equations.
void check_field_finite(const AgentSpec& a, const Field& dynamics);

// `tracker` as written: a tracker's name or block ({name, params}), or `auto` (also when absent).
struct TrackerRequest {
  bool automatic = true;
  PluginChoice choice;
  Field field;  // where it was written (not present: the default, auto)
};

TrackerRequest read_tracker_request(const Field& f, const PluginRegistry& reg);

// Resolves the agent's tracker (AgentSpec::tracker) by the trackers' own assessments; a refusal
// (or, for auto, every tracker's) is a located error at the field the tracker names. The
// trackers judge their estimates against `budget`.
AgentTrackers resolve_tracker(AgentSpec& a, const TrackerRequest& req, TrackerInstances& trackers,
                              const PluginRegistry& reg, const Problem& pb, const MemoryBudget& budget, const Field& af,
                              const Field& defaults);

}  // namespace marsyn::loader
