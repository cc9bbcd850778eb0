#pragma once
// How loose a verified funnel is (issue 23, item 6): per step k and state coordinate i, the
// verified half-width (the hull of V_k about the nominal x_k) next to the largest |x_i - x_k,i|
// seen in closed-loop runs under adversarial disturbances (sampled, and the linearized worst cases). A statistic only: sampling
// never enters the guarantee. The ratio is >= 1 up to sampling; the closer to 1, the tighter.
#include <cstdint>
#include <string>
#include <vector>

#include "funnel_controller.hpp"
#include "marsyn/dynamics.hpp"

namespace marsyn::funnel {

struct Tightness {
  std::vector<std::vector<double>> verified;  // (T + 1) x n half-widths about x_k
  std::vector<std::vector<double>> sampled;   // (T + 1) x n largest deviations seen
  std::vector<double> coordinate_median;      // n: median over steps k >= 1 of verified / sampled
  double median = 0.0;                        // over every (k >= 1, i) with a deviation seen
  double max = 0.0;
  int runs = 0;
};

// `verified`: (T + 1) x n half-widths from the verification. `runs` runs start at vertices of
// V_0 and face, in turn, a constant vertex of [-W, W], a vertex switching 8 times per period, a
// vertex re-drawn every fine step, and a push away from the nominal (w_i = W_i sign(x_i - x_k,i)).
// Then (when runs > 0) the linearized closed loop's worst cases: for each coordinate, sign and
// one of 4 target steps (T/4, T/2, 3T/4, T), the vertex sequence and initial vertex that maximize that deviation to
// first order (exact for linear systems), each run to the end.
Tightness measure_tightness(const Dynamics& f, const FunnelController& ctrl, std::vector<std::vector<double>> verified,
                            int runs, std::uint64_t seed);

// "median 2.1x, max 3.4x (worst coordinate theta 2.9x)".
std::string describe(const Tightness& t, const std::vector<std::string>& names);

}  // namespace marsyn::funnel
