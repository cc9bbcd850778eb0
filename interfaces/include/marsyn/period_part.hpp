#pragma once
// Part `part` of step k's sampling period split into `parts` equal parts, as every tracker makes
// its period enclosures (tracker.hpp, PeriodEnclosure): [k + part/parts, k + (part+1)/parts] tau,
// written once so that the certifier, which pairs agents' enclosures by part index, reads the same
// times from every tracker. The boxes are sized (n states, `workspace_dim` coordinates) for the
// tracker to fill.
#include "marsyn/tracker.hpp"

namespace marsyn {

inline PeriodEnclosure period_part(int k, int part, int parts, double tau, int n, int workspace_dim) {
  PeriodEnclosure e;
  e.step = k;
  e.t0 = tau * (k + static_cast<double>(part) / parts);
  e.t1 = tau * (k + static_cast<double>(part + 1) / parts);
  e.state.lo.resize(n);
  e.state.hi.resize(n);
  e.workspace.lo.resize(workspace_dim);
  e.workspace.hi.resize(workspace_dim);
  return e;
}

}  // namespace marsyn
