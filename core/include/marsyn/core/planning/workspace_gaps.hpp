#pragma once
// Gaps an agent cannot pass at any horizon: two obstacles, or an obstacle and the edge of the
// agent's workspace, closer than 2 (delta + margin) in the problem's norm. A plan through such a
// gap is infeasible however long the horizon, so `check` warns about it and a failed plan names
// it instead of suggesting a longer horizon.
#include <string>
#include <vector>

#include "marsyn/problem.hpp"

namespace marsyn::planning {

struct NarrowGap {
  std::string first, second;        // obstacle names, or "the edge x >= lo of <agent>'s workspace" etc.
  double width = 0.0;               // the gap's width in the problem's norm
  double needed = 0.0;              // the largest 2 (delta + margin) among the agents it closes
  std::vector<std::string> agents;  // the agents it is closed to
};

// Every closed gap (width > 0: overlapping obstacles form one obstacle, not a gap). The margin
// is the largest per-coordinate workspace margin over the agent's state bounds (for a linear
// workspace its eps in the mapped coordinates), so `needed` is what the eps-robust plan keeps
// on both sides.
std::vector<NarrowGap> narrow_gaps(const Problem& problem);

// One line: "obstacles A and B leave a gap 0.62 wide (inf-norm); passing it needs 0.88
// (2 (delta + eps)): closed to drone1, drone2 at every horizon".
std::string describe(const NarrowGap& gap);

}  // namespace marsyn::planning
