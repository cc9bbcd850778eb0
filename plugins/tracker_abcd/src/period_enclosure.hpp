#pragma once
// The continuous-time half of the tracker's guarantee: where the closed loop can be between two
// samples. For every step k, every winning cell of step k and its stored input, the a priori
// enclosures of the successor computation (successor_box.hpp) bound every state over each part
// of the period; the hull over a step's winning cells, part by part, is what a certifier checks
// against the specification (docs/soundness.md, "Continuous time").
#include <string>
#include <vector>

#include "controller_file.hpp"
#include "marsyn/tracker.hpp"
#include "successor_box.hpp"

namespace marsyn::abcd {

struct EnclosureOptions {
  int substeps = 4;  // parts of each period, each with its own box
  int threads = 1;
};

// Fills d.enclosures for steps 0..T-1 of a tracking controller. Cells that differ only along
// coordinates the field does not read (`invariant`) share one enclosure computation over their
// hull: translating the state along them translates every solution, so this is as tight as
// one computation per cell. Returns false (with `why`) when some winning cell has no enclosure.
bool compute_period_enclosures(const TrackingProblem& p, const std::vector<bool>& invariant, const SuccessorBox& sb,
                               const EnclosureOptions& o, ControllerData& d, std::string& why);

}  // namespace marsyn::abcd
