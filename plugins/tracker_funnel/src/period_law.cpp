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
PeriodLaw::Rows PeriodLaw::rows(const Zonotope& zx, int k) const {
  const int n = d_.n, m = d_.m, N = n + m;
  const StepSet& sk = d_.sets[k];
  const auto& xk = p_.nominal.x[k];
  const int pg = zx.generators();
  Rows r;
  r.center.assign(N, FastInterval(0.0));
  r.gens = IMatrix(N, pg);
  r.fb.assign(m, FastInterval(0.0));
  r.round.assign(m, 0.0);
  r.meas.assign(m, 0.0);
  r.spread.assign(m, 0.0);
  for (int i = 0; i < n; ++i) {
    r.center[i] = fi(zx.c[i]);
    for (int l = 0; l < pg; ++l) r.gens(i, l) = fi(zx.G(i, l));
  }
  for (int i = 0; i < m; ++i) {
    // The feedback part K (x - x_k) over the set: centre, generators and rounding, which do not
    // depend on u_k but for |u_k| in the rounding allowance.
    for (int j = 0; j < n; ++j) {
      r.fb[i] += fi(K_[k](i, j)) * (fi(zx.c[j]) - fi(xk[j]));
      r.round[i] = add_up(r.round[i], mul_up(std::fabs(K_[k](i, j)), reach(sk.lo[j], sk.hi[j], xk[j])));
      // The controller sees the measured (double) state, not the real one.
      r.meas[i] = add_up(r.meas[i], mul_up(std::fabs(K_[k](i, j)), measured(sk.lo[j], sk.hi[j])));
    }
    for (int l = 0; l < pg; ++l) {
      FastInterval g(0.0);
      for (int j = 0; j < n; ++j) g += fi(K_[k](i, j)) * fi(zx.G(j, l));
      r.gens(n + i, l) = g;
      r.spread[i] = add_up(r.spread[i], mag(g));
    }
  }
  return r;
}

FastInterval PeriodLaw::row_hull(const Rows& r, int i, double ui, FastInterval& c, double& delta) const {
  c = fi(ui) + r.fb[i];
  delta = add_up(add_up(mul_up(kappa_, add_up(std::fabs(ui), r.round[i])), kTiny), r.meas[i]);
  return c + FastInterval(-add_up(r.spread[i], delta), add_up(r.spread[i], delta));
}

Period PeriodLaw::enclose(Rows r, int k, const std::vector<double>& u) const {
  const int n = d_.n, m = d_.m, N = n + m;
  const int pg = r.gens.cols;
  std::vector<double> extra(N, 0.0);
  Period out_p;
  out_p.u = u;
  out_p.boxed.assign(m, 0);
  for (int i = 0; i < m; ++i) {
    out_p.shifted |= u[i] != p_.nominal.u[k][i];
    FastInterval c;
    double delta;
    out_p.nominal_hull.push_back(row_hull(r, i, p_.nominal.u[k][i], c, delta));
    const FastInterval hull = row_hull(r, i, u[i], c, delta);
    const double lo = d_.u_lo[i], hi = d_.u_hi[i];
    if (hull.lower() >= lo && hull.upper() <= hi) {
      r.center[n + i] = c;
      extra[n + i] = delta;
    } else {
      // Saturation: sat_U maps the hull's values into [sat(lo), sat(hi)]; the row keeps that
      // interval and loses its correlation with the state (sound, less tight).
      out_p.saturated = true;
      out_p.boxed[i] = 1;
      const double a = std::clamp(hull.lower(), lo, hi);
      const double b = std::clamp(hull.upper(), lo, hi);
      r.center[n + i] = FastInterval(a, b);
      for (int l = 0; l < pg; ++l) r.gens(n + i, l) = FastInterval(0.0);
    }
  }
  const Zonotope za = from_intervals(r.center, r.gens, extra);
  out_p.fr = enclose_period(*p_.dynamics, za, d_.dist, 0, flow_);
  return out_p;
}

// The move is by the overshoot (and a hair, for the rounding of the move itself) when the hull
// is narrower than U: the row stays affine in the generators (no saturation), at the price of
// pulling the closed loop off the nominal by the move (docs/funnel.md, "Inputs at a bound of U").
std::vector<double> PeriodLaw::shifted(const std::vector<Rows>& rows, int k, bool& moved) const {
  const int m = d_.m;
  std::vector<double> u(p_.nominal.u[k].data(), p_.nominal.u[k].data() + m);
  moved = false;
  FastInterval c;
  double delta;
  for (int i = 0; i < m; ++i) {
    const double lo = d_.u_lo[i], hi = d_.u_hi[i];
    double a = std::numeric_limits<double>::infinity(), b = -a;  // the hull over every part
    for (const Rows& r : rows) {
      const FastInterval h = row_hull(r, i, u[i], c, delta);
      a = std::min(a, h.lower());
      b = std::max(b, h.upper());
    }
    if ((a >= lo && b <= hi) || !(b - a < hi - lo)) continue;
    const double over = b > hi ? b - hi : a - lo;
    const double to = u[i] - over - std::copysign(1e-9 * (hi - lo), over);
    if (!std::isfinite(to)) continue;
    bool inside = true;
    for (const Rows& r : rows) {
      const FastInterval h = row_hull(r, i, to, c, delta);
      inside = inside && h.lower() >= lo && h.upper() <= hi;
    }
    if (inside) {
      u[i] = to;
      moved = true;
    }
  }
  return u;
}

Period PeriodLaw::with_input(const Zonotope& zx, int k, const std::vector<double>& u) const {
  return enclose(rows(zx, k), k, u);
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

std::vector<Period> PeriodLaw::best(const std::vector<const Zonotope*>& parts, int k) const {
  std::vector<Rows> r;
  for (const Zonotope* z : parts) r.push_back(rows(*z, k));
  const std::vector<double> nominal(p_.nominal.u[k].data(), p_.nominal.u[k].data() + d_.m);
  std::vector<Period> a;
  bool saturated = false;
  for (const Rows& x : r) {
    a.push_back(enclose(x, k, nominal));
    saturated |= a.back().saturated;
  }
  if (!saturated || !shift_inputs_) return a;
  bool moved = false;
  const std::vector<double> u = shifted(r, k, moved);
  if (!moved) return a;
  std::vector<Period> b;
  double reach_a = 0.0, reach_b = 0.0;
  for (std::size_t q = 0; q < r.size(); ++q) {
    b.push_back(enclose(std::move(r[q]), k, u));
    reach_a = std::max(reach_a, end_reach(a[q].fr, k + 1));
    reach_b = std::max(reach_b, end_reach(b[q].fr, k + 1));
  }
  return reach_b < reach_a ? b : a;
}

}  // namespace marsyn::funnel
