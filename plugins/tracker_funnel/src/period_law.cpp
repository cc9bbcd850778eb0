#include "period_law.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "allowances.hpp"
#include "funnel_synthesis.hpp"

namespace marsyn::funnel {
namespace {

using fast_detail::add_up;
using fast_detail::mul_up;

FastInterval fi(double v) { return FastInterval(v); }

}  // namespace

PeriodLaw::PeriodLaw(const TrackingProblem& p, const std::vector<Eigen::MatrixXd>& K, const FunnelData& d,
                     const FlowOptions& flow, bool shift_inputs)
    : p_(p), K_(K), d_(d), flow_(flow), shift_inputs_(shift_inputs), kappa_(rounding_factor(d.n + 1)) {}

// The closed loop's start at step k over (x, u): u = u_k + K_k (x - x_k) is affine in the
// generators; the controller's rounding adds at most kappa (|u_k| + |K| |x - x_k|) per input.
// `u` is the law's u_k as the controller will store it: the nominal's input, or (shift) that
// input moved by the least amount that keeps the row's hull inside U (docs/funnel.md, "Inputs
// at a bound of U").
Period PeriodLaw::period(const Zonotope& zx, int k, bool shift) const {
  const TrackingProblem& p = p_;
  const FunnelData& d = d_;
  const int n = d.n, m = d.m, N = n + m;
  const double kappa = kappa_;
  const StepSet& sk = d.sets[k];
  const auto& xk = p.nominal.x[k];
  const int pg = zx.generators();
  IVector center(N);
  IMatrix gens(N, pg);
  std::vector<double> extra(N, 0.0);
  for (int i = 0; i < n; ++i) {
    center[i] = fi(zx.c[i]);
    for (int l = 0; l < pg; ++l) gens(i, l) = fi(zx.G(i, l));
  }
  Period out_p;
  out_p.u.assign(p.nominal.u[k].data(), p.nominal.u[k].data() + m);
  for (int i = 0; i < m; ++i) {
    // The feedback part K (x - x_k) over the set: centre, generators and rounding, which do not
    // depend on u_k but for |u_k| in the rounding allowance.
    FastInterval fb(0.0);
    double round = 0.0, meas = 0.0;
    for (int j = 0; j < n; ++j) {
      fb += fi(K_[k](i, j)) * (fi(zx.c[j]) - fi(xk[j]));
      round = add_up(round, mul_up(std::fabs(K_[k](i, j)), reach(sk.lo[j], sk.hi[j], xk[j])));
      // The controller sees the measured (double) state, not the real one.
      meas = add_up(meas, mul_up(std::fabs(K_[k](i, j)), measured(sk.lo[j], sk.hi[j])));
    }
    double spread = 0.0;
    for (int l = 0; l < pg; ++l) {
      FastInterval g(0.0);
      for (int j = 0; j < n; ++j) g += fi(K_[k](i, j)) * fi(zx.G(j, l));
      gens(n + i, l) = g;
      spread = add_up(spread, mag(g));
    }
    // The row for the law's input ui: its centre, rounding allowance and hull.
    auto row = [&](double ui, FastInterval& c, double& delta) {
      c = fi(ui) + fb;
      delta = add_up(add_up(mul_up(kappa, add_up(std::fabs(ui), round)), kTiny), meas);
      return c + FastInterval(-add_up(spread, delta), add_up(spread, delta));
    };
    FastInterval c;
    double delta;
    FastInterval hull = row(out_p.u[i], c, delta);
    const double lo = d.u_lo[i], hi = d.u_hi[i];
    if (shift && !(hull.lower() >= lo && hull.upper() <= hi) && hull.upper() - hull.lower() < hi - lo) {
      // Move u_k by the overshoot (and a hair, for the rounding of the move itself) when the
      // hull is narrower than U: the row stays affine in the generators (no saturation), at
      // the price of pulling the closed loop off the nominal by the move.
      const double over = hull.upper() > hi ? hull.upper() - hi : hull.lower() - lo;
      const double moved = out_p.u[i] - over - std::copysign(1e-9 * (hi - lo), over);
      FastInterval c2;
      double delta2;
      const FastInterval hull2 = row(moved, c2, delta2);
      if (std::isfinite(moved) && hull2.lower() >= lo && hull2.upper() <= hi) {
        out_p.u[i] = moved;
        out_p.shifted = true;
        c = c2;
        delta = delta2;
        hull = hull2;
      }
    }
    if (hull.lower() >= lo && hull.upper() <= hi) {
      center[n + i] = c;
      extra[n + i] = delta;
    } else {
      // Saturation: sat_U maps the hull's values into [sat(lo), sat(hi)]; the row keeps that
      // interval and loses its correlation with the state (sound, less tight).
      out_p.saturated = true;
      const double a = std::clamp(hull.lower(), lo, hi);
      const double b = std::clamp(hull.upper(), lo, hi);
      center[n + i] = FastInterval(a, b);
      for (int l = 0; l < pg; ++l) gens(n + i, l) = FastInterval(0.0);
    }
  }
  const Zonotope za = from_intervals(center, gens, extra);
  out_p.fr = enclose_period(*p.dynamics, za, d.w, 0, flow_);
  return out_p;
}

double PeriodLaw::end_reach(const FlowResult& fr, int k1) const {
  if (!fr.ok) return std::numeric_limits<double>::infinity();
  double worst = 0.0;
  for (int i = 0; i < d_.n; ++i) {
    double r = std::fabs(fr.end.c[i] - p_.nominal.x[k1][i]);
    for (Eigen::Index j = 0; j < fr.end.G.cols(); ++j) r += std::fabs(fr.end.G(i, j));
    worst = std::max(worst, r / p_.tube.eps[i]);
  }
  return worst;
}

Period PeriodLaw::best(const Zonotope& zx, int k) const {
  Period a = period(zx, k, false);
  if (!a.saturated || !shift_inputs_) return a;
  Period b = period(zx, k, true);
  if (!b.shifted) return a;
  return end_reach(b.fr, k + 1) < end_reach(a.fr, k + 1) ? b : a;
}

}  // namespace marsyn::funnel
