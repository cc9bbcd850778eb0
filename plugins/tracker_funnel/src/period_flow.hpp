#pragma once
// One sampling period of the closed loop, enclosed soundly. The input is held over the period
// (zero-order hold) and depends on the state at the sample, so the flow is enclosed for the
// augmented state z = (x, u), u' = 0: a zonotope over (x, u) keeps the correlation between the
// state and its own feedback input. docs/soundness.md section 11 has the argument.
#include <cstddef>
#include <vector>

#include "marsyn/disturbance.hpp"
#include "marsyn/dynamics.hpp"
#include "zonotope.hpp"

namespace marsyn::funnel {

// How the Euler part x + h f(x, u) over the zonotope is linearized (docs/soundness.md section 11).
enum class Remainder {
  // Mean value about the centre: the midpoint of the interval Jacobian over the hull acts on the
  // generators, |[J](hull) - Jm| radii is the error (grows like the Jacobian's spread x size).
  MeanValue,
  // Linearization at the centre plus the Lagrange remainder 1/2 |[H](hull)| radii radii
  // (grows with the square of the size); per state row the smaller of this and the mean-value
  // bound is kept, both being sound for that row.
  SecondOrder,
};

struct FlowOptions {
  double tau = 0.1;
  Remainder remainder = Remainder::SecondOrder;
  // Test hook: multiplies the Lagrange remainder (1: sound; < 1 only to show a test can fail).
  double remainder_scale = 1.0;
  int substeps = 16;          // enclosure steps per period (a multiple of the period's parts)
  int picard_iterations = 20;
  int max_generators = 0;     // 0: 3 (n + m)
  // Substeps after which the box of new errors becomes generators (carried exactly by the linear
  // part from then on, instead of by |I + h L|); 0: once, at the period's end.
  int box_substeps = 0;
};

struct FlowResult {
  bool ok = false;
  Zonotope end;                     // over (x, u) at the end of the period
  std::vector<FastInterval> boxes;  // substeps x n: every state during each substep
  long rows = 0, second_order_rows = 0;  // state rows enclosed, and of them by the Lagrange form
};

// sum_k a[k] b[k b_stride] over k < N, enclosed: the round-to-nearest sum widened by the a priori
// bound of its rounding error (docs/soundness.md section 2). Not finite: (-inf, inf).
FastInterval dot_enclosure(const double* a, const double* b, std::ptrdiff_t b_stride, int N);

// `start` lives in R^{n+m} (states first, then inputs) and contains every (x(t0), u) the closed
// loop can have at the sample; w bounds the disturbance (n numbers). For every such start and
// every measurable w(.) with values in [-w, w], the solution at t0 + tau lies in result.end and
// during substep s in boxes[s n .. s n + n). The first `basis` generators of `start` are kept in
// front through the whole period (the caller fits its verified set to their image).
// Runs in round-to-nearest (the caller holds a RoundToNearestScope).
FlowResult enclose_period(const Dynamics& f, const Zonotope& start, const std::vector<double>& w, int basis,
                          const FlowOptions& opt);
// The same under a disturbance bound that may grow with the state and input: each substep
// takes W over its own a priori box and input range (docs/soundness.md section 12).
FlowResult enclose_period(const Dynamics& f, const Zonotope& start, const DisturbanceBound& w, int basis,
                          const FlowOptions& opt);

}  // namespace marsyn::funnel
