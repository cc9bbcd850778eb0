#pragma once
// One sampling period of the closed loop, enclosed soundly. The input is held over the period
// (zero-order hold) and depends on the state at the sample, so the flow is enclosed for the
// augmented state z = (x, u), u' = 0: a zonotope over (x, u) keeps the correlation between the
// state and its own feedback input. docs/soundness.md section 11 has the argument.
#include <vector>

#include "marsyn/dynamics.hpp"
#include "zonotope.hpp"

namespace marsyn::funnel {

struct FlowOptions {
  double tau = 0.1;
  int substeps = 16;          // enclosure steps per period (a multiple of the period's parts)
  int picard_iterations = 20;
  int max_generators = 0;     // 0: 3 (n + m)
};

struct FlowResult {
  bool ok = false;
  Zonotope end;                     // over (x, u) at the end of the period
  std::vector<FastInterval> boxes;  // substeps x n: every state during each substep
};

// `start` lives in R^{n+m} (states first, then inputs) and contains every (x(t0), u) the closed
// loop can have at the sample; w bounds the disturbance (n numbers). For every such start and
// every measurable w(.) with values in [-w, w], the solution at t0 + tau lies in result.end and
// during substep s in boxes[s n .. s n + n). The first `basis` generators of `start` are kept in
// front through the whole period (the caller fits its verified set to their image).
// Runs in round-to-nearest (the caller holds a RoundToNearestScope).
FlowResult enclose_period(const Dynamics& f, const Zonotope& start, const std::vector<double>& w, int basis,
                          const FlowOptions& opt);

}  // namespace marsyn::funnel
