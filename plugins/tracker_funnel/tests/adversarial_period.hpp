#pragma once
// One sampling period of a funnel controller's closed loop, as the soundness tests run it: the
// input held, the disturbance a constant vertex of W, a vertex switching 8 times, or uniform
// (redrawn 8 times), RK4 at tau / 32; at every fine step, whether the state lies in its part's
// period enclosure, and in the same shrunk by 10 % (the mutation that must leak).
#include <algorithm>
#include <random>
#include <vector>

#include "funnel_controller.hpp"
#include "marsyn/sampled_map.hpp"

namespace marsyn::funnel::testing {

struct PeriodCheck {
  long fine_states = 0, enclosure_leaks = 0, shrunk_enclosure_leaks = 0;
};

// x: the state at sample k, on return the state at k + 1. `truth`: the W(x, u) the runs draw in
// (default the controller's own); a vertex of it stays a vertex, scaled at each fine step to W
// at the state and input there.
inline void adversarial_period(const Dynamics& f, const FunnelData& d, int k, std::vector<double>& x, const std::vector<double>& u,
                               std::mt19937_64& rng, PeriodCheck& c, const DisturbanceBound* truth = nullptr) {
  constexpr int kFine = 32, kPieces = 8;
  const int n = d.n, P = static_cast<int>(d.enclosures.size()) / d.horizon();
  const DisturbanceBound& dist = truth ? *truth : d.dist;
  std::uniform_real_distribution<double> U(-1, 1), U01(0, 1);
  std::vector<double> unit(n), w(n), wx(n), nxt(n);
  const int mode = static_cast<int>(U01(rng) * 3);
  for (int piece = 0; piece < kPieces; ++piece) {
    if (piece == 0 || mode == 1)
      for (int i = 0; i < n; ++i) unit[i] = U01(rng) < 0.5 ? -1 : 1;
    if (mode == 2)
      for (int i = 0; i < n; ++i) unit[i] = U(rng);
    for (int q = 0; q < kFine / kPieces; ++q) {
      if (dist.dim() == n) dist.at(x.data(), u.data(), wx.data());
      else wx = d.w;  // a controller read back: W = w
      for (int i = 0; i < n; ++i) w[i] = unit[i] * wx[i];
      rk4_step<double>(f, x.data(), u.data(), w.data(), d.tau / kFine, 1, nxt.data());
      x = nxt;
      const int fine = piece * (kFine / kPieces) + q + 1;  // time fine / kFine of the period
      const PeriodEnclosure& e = d.enclosures[static_cast<std::size_t>(k) * P + std::min(P - 1, fine * P / kFine)];
      ++c.fine_states;
      bool in = true, in_shrunk = true;
      for (int i = 0; i < n; ++i) {
        const double lo = e.state.lo[i], hi = e.state.hi[i], cut = 0.05 * (hi - lo);
        in = in && x[i] >= lo && x[i] <= hi;
        in_shrunk = in_shrunk && x[i] >= lo + cut && x[i] <= hi - cut;
      }
      c.enclosure_leaks += !in;
      c.shrunk_enclosure_leaks += !in_shrunk;
    }
  }
}

}  // namespace marsyn::funnel::testing
