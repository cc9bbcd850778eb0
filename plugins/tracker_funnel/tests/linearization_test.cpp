// The second-order (Lagrange) linearization of the flow enclosure, checked against sampling:
// - the interval Hessian over a box encloses the exact (DualD2) Hessian and central second
//   differences at points of the box, and on tiny boxes it is tight (shrunk by 10% it misses
//   sampled values, so a wrong or scaled-down bound is caught);
// - the remainder bound holds at sampled points of the box (0 violations per model) and is
//   attained: shrunk by 10% (the remainder_scale hook at 0.9), sampled corners exceed it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "funnel_scenarios.hpp"
#include "linearization.hpp"

namespace marsyn::funnel {
namespace {

using testing::scenario;

struct Box {
  std::vector<double> c, rad;
  IVector X, C;
};

// A box around a nominal state and input of the scenario, half-widths `scale` x eps (states)
// and `scale` x a tenth of the input range (inputs).
Box box_near(const TrackingProblem& p, std::mt19937_64& rng, double scale) {
  const int n = p.dynamics->state_dim(), m = p.dynamics->input_dim();
  std::uniform_int_distribution<int> K(0, static_cast<int>(p.nominal.u.size()) - 1);
  std::uniform_real_distribution<double> U(-1, 1);
  const int k = K(rng);
  Box b;
  for (int i = 0; i < n; ++i) {
    b.c.push_back(p.nominal.x[k][i] + 0.5 * p.tube.eps[i] * U(rng));
    b.rad.push_back(scale * p.tube.eps[i]);
  }
  for (int j = 0; j < m; ++j) {
    b.c.push_back(p.nominal.u[k][j]);
    b.rad.push_back(scale * 0.1 * (p.input_bounds.hi[j] - p.input_bounds.lo[j]));
  }
  for (std::size_t i = 0; i < b.c.size(); ++i) {
    b.X.push_back(FastInterval(b.c[i] - b.rad[i], b.c[i] + b.rad[i]));
    b.C.push_back(FastInterval(b.c[i]));
  }
  return b;
}

void exact_hessian(const Dynamics& f, const std::vector<double>& z, std::vector<double>& H, std::vector<double>& value) {
  const int n = f.state_dim(), m = f.input_dim(), N = n + m;
  std::vector<DualD2> zd(N), out(n);
  for (int i = 0; i < N; ++i) zd[i] = second_order_variable(z[i], i, N);
  f.field(zd.data(), zd.data() + n, out.data());
  H.assign(static_cast<std::size_t>(n) * N * N, 0.0);
  value.resize(n);
  for (int i = 0; i < n; ++i) {
    value[i] = out[i].v.v;
    for (int j = 0; j < N; ++j)
      for (int k = 0; k < N; ++k) H[(static_cast<std::size_t>(i) * N + j) * N + k] = second_derivative(out[i], j, k);
  }
}

std::vector<double> eval(const Dynamics& f, const std::vector<double>& z) {
  std::vector<double> out(f.state_dim());
  f.field(z.data(), z.data() + f.state_dim(), out.data());
  return out;
}

class Linearization2 : public ::testing::TestWithParam<std::string> {};

TEST_P(Linearization2, HessianEnclosesSampledSecondDerivatives) {
  const TrackingProblem p = scenario(GetParam());
  const Dynamics& f = *p.dynamics;
  const RoundToNearestScope nearest;
  const int n = f.state_dim(), N = n + f.input_dim();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  long checked = 0, outside = 0, fd_outside = 0, tight = 0, tight_entries = 0;
  std::vector<double> He, val;
  for (int box = 0; box < 200; ++box) {
    const bool tiny = box % 2 == 1;
    const Box b = box_near(p, rng, tiny ? 1e-7 : 0.3);
    IMatrix J;
    std::vector<FastInterval> H;
    interval_hessian(f, b.X.data(), J, H);
    std::vector<double> hmax(H.size(), 0.0);
    for (int s = 0; s < 20; ++s) {
      std::vector<double> z(N);
      for (int i = 0; i < N; ++i) z[i] = b.c[i] + b.rad[i] * (U(rng) < 0.3 ? (U(rng) < 0 ? -1 : 1) : U(rng)) * 0.999;
      exact_hessian(f, z, He, val);
      for (std::size_t e = 0; e < H.size(); ++e) {
        ++checked;
        const double tol = 1e-12 * (1 + std::fabs(He[e]));
        if (!(He[e] >= H[e].lower() - tol && He[e] <= H[e].upper() + tol)) ++outside;
        hmax[e] = std::max(hmax[e], std::fabs(He[e]));
      }
      if (tiny) continue;
      // Central second differences inside the box (step 1e-4 of the radius).
      for (int j = 0; j < N; ++j)
        for (int k = j; k < N; ++k) {
          const double dj = 1e-4 * b.rad[j], dk = 1e-4 * b.rad[k];
          if (!(dj > 0 && dk > 0)) continue;
          auto at = [&](double sj, double sk) {
            std::vector<double> y = z;
            y[j] += sj * dj;
            y[k] += sk * dk;
            return eval(f, y);
          };
          const auto pp = at(1, 1), pm = at(1, -1), mp = at(-1, 1), mm = at(-1, -1);
          for (int i = 0; i < n; ++i) {
            const double fd = (pp[i] - pm[i] - mp[i] + mm[i]) / (4 * dj * dk);
            const FastInterval& h = H[(static_cast<std::size_t>(i) * N + j) * N + k];
            const double tol = 1e-5 * (1 + mag(h));
            if (!(fd >= h.lower() - tol && fd <= h.upper() + tol)) ++fd_outside;
          }
        }
    }
    if (!tiny) continue;
    // On a tiny box the enclosure is the point value up to rounding: 0.9 of it is too small.
    for (std::size_t e = 0; e < H.size(); ++e) {
      if (mag(H[e]) < 1e-6) continue;
      ++tight_entries;
      tight += 0.9 * mag(H[e]) < hmax[e];
    }
  }
  EXPECT_EQ(outside, 0) << "of " << checked;
  EXPECT_EQ(fd_outside, 0);
  EXPECT_GT(tight_entries, 0);
  EXPECT_EQ(tight, tight_entries) << "Hessian bounds on tiny boxes more than 10% above the sampled values";
}

TEST_P(Linearization2, RemainderBoundHoldsAndIsAttained) {
  const TrackingProblem p = scenario(GetParam());
  const Dynamics& f = *p.dynamics;
  const RoundToNearestScope nearest;
  const int n = f.state_dim(), N = n + f.input_dim();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(-1, 1), U01(0, 1);
  long violations = 0, mv_violations = 0, samples = 0;
  double best_fraction = 0.0;  // largest sampled remainder / bound over rows and boxes
  for (int box = 0; box < 100; ++box) {
    // Large boxes for the bound; small ones, where the Hessian is nearly constant over the box,
    // for how close samples come to it.
    const bool small = box % 2 == 1;
    const Box b = box_near(p, rng, small ? 0.02 : 0.5);
    const Linearization so = second_order_linearization(f, b.X.data(), b.C.data(), b.rad);
    const Linearization mv = mean_value_linearization(f, b.X.data(), b.rad);
    const std::vector<double> fc = eval(f, b.c);
    std::vector<double> worst(n, 0.0);
    for (int s = 0; s < 2000; ++s) {
      std::vector<double> z(N);
      for (int i = 0; i < N; ++i) z[i] = b.c[i] + b.rad[i] * (U01(rng) < 0.7 ? (U01(rng) < 0.5 ? -1.0 : 1.0) : U(rng));
      const std::vector<double> fz = eval(f, z);
      ++samples;
      for (int i = 0; i < n; ++i) {
        double lin_so = 0, lin_mv = 0;
        for (int k = 0; k < N; ++k) {
          lin_so += so.L(i, k) * (z[k] - b.c[k]);
          lin_mv += mv.L(i, k) * (z[k] - b.c[k]);
        }
        // The check's own rounding: a few ulps of the terms involved.
        const double tol = 1e-13 * (1 + std::fabs(fz[i]) + std::fabs(fc[i]) + std::fabs(lin_so) + std::fabs(lin_mv));
        const double e_so = std::fabs(fz[i] - fc[i] - lin_so), e_mv = std::fabs(fz[i] - fc[i] - lin_mv);
        violations += e_so > so.bound[i] + tol;
        mv_violations += e_mv > mv.bound[i] + tol;
        worst[i] = std::max(worst[i], e_so);
      }
    }
    for (int i = 0; i < n && small; ++i)
      if (so.bound[i] > 1e-12) best_fraction = std::max(best_fraction, worst[i] / so.bound[i]);
  }
  EXPECT_EQ(violations, 0) << "of " << samples * n;
  EXPECT_EQ(mv_violations, 0);
  // Shrunk by 10% (remainder_scale 0.9) the bound is exceeded by some sampled corner.
  EXPECT_GT(best_fraction, 0.9) << "the remainder bound is never approached by samples";
  std::printf("%s: largest sampled remainder / bound %.3f\n", GetParam().c_str(), best_fraction);
}

INSTANTIATE_TEST_SUITE_P(Models, Linearization2,
                         ::testing::Values("unicycle", "crane", "bicycle", "planar_quadrotor", "quadrotor"));

}  // namespace
}  // namespace marsyn::funnel
