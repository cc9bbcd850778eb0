#pragma once
// The LTL form of a mission (docs/tasks.md, "LTL form"): `ltl: "F(a & F(b & F goal)) & G !shelf"`
// over the problem's named `regions`, read to the same stages as the `stages:` list it stands for.
#include <string>
#include <vector>

#include "marsyn/problem.hpp"
#include "yaml_reader.hpp"

namespace marsyn::loader {

using yaml::Field;

// A `G !name` of a formula: checked against the obstacles once they are read.
struct LtlAvoid {
  std::string name;
  int column = 0;  // 1-based, in the formula
};

struct LtlMission {
  std::vector<MissionStage> stages;  // one per region of the F chain, in visiting order
  std::vector<LtlAvoid> avoid;
};

// The top-level `regions` map: each key a name usable in a formula (not a reserved word).
void check_regions(const Field& regions);

// Parses agent a's formula `f` (a's dynamics, bounds, eps and workspace already read) over
// `regions`; each region is checked for a as a stage's `region` is, the sequence against
// `horizon`. Anything outside the fragment is a located error naming the operator and its column.
LtlMission read_ltl(const Field& f, const Field& regions, const AgentSpec& a, int horizon);

// Every `G !name` names an obstacle of the problem, or `obstacles` (all of them).
void check_ltl_avoid(const Field& f, const std::vector<LtlAvoid>& avoid, const std::vector<Obstacle>& obstacles);

}  // namespace marsyn::loader
