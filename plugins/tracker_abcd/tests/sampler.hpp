#pragma once
// Randomized soundness check of successor boxes: sample states in a cell (uniformly, plus its
// corners), a grid input and disturbances (uniform per substep, a constant vertex of W, or a
// vertex switching inside the period), integrate finely with RK4, and count successors outside
// the box. `shrink` cuts the box by that fraction of its radius on every side, which must make
// escapes appear: the check can fail.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "tube_simulation.hpp"
#include "input_grid.hpp"
#include "successor_cache.hpp"
#include "uniform_grid.hpp"

namespace marsyn::abcd::testing {

struct SamplerSetup {
  const Dynamics* f = nullptr;
  std::vector<double> origin, eta_x, w, u_lo, u_hi, eta_u;
  std::vector<double> region_lo, region_hi;  // cells are drawn with centres in this box
  double tau = 0.1;
  int boxes = 400;
  int samples_per_box = 2500;
  int substeps = 20;
  double shrink = 0.0;
  std::uint64_t seed = 1;
  SuccessorOptions successor{};
  const SuccessorHook* hook = nullptr;
};

struct SamplerResult {
  long long samples = 0, escapes = 0;  // escapes from the absolute box
  long long cover_escapes = 0;         // successors whose cell is outside the reused (shifted) cover
  long long unbounded = 0;             // (cell, input) pairs without a box (skipped)
  double worst = 0.0;                  // largest escape distance / cell size
};

inline SamplerResult sample_successors(const SamplerSetup& s) {
  const Dynamics& f = *s.f;
  const int n = f.state_dim(), m = f.input_dim();
  UniformGrid g(s.origin, s.eta_x);
  InputGrid ug(s.u_lo, s.u_hi, s.eta_u);
  SuccessorOptions so = s.successor;
  so.tau = s.tau;
  SuccessorBox sb(f, s.w, so, s.hook);
  auto inv = f.field_independent_of();
  SuccessorTable tab(sb, g, ug, inv);
  std::mt19937_64 rng(s.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  SamplerResult r;
  for (int b = 0; b < s.boxes; ++b) {
    std::int64_t idx[kMaxDim];
    for (int i = 0; i < n; ++i) {
      const double x = s.region_lo[i] + unit(rng) * (s.region_hi[i] - s.region_lo[i]);
      idx[i] = g.index(i, x);
    }
    const std::int64_t j = static_cast<std::int64_t>(unit(rng) * static_cast<double>(ug.size())) % ug.size();
    double lo[kMaxDim], hi[kMaxDim];
    if (!tab.absolute(idx, j, lo, hi)) {
      ++r.unbounded;
      continue;
    }
    for (int i = 0; i < n; ++i) {
      const double rad = 0.5 * (hi[i] - lo[i]);
      lo[i] += s.shrink * rad;
      hi[i] -= s.shrink * rad;
    }
    RelBox& e = tab.entry(idx, j);
    tab.box(e, idx, j);
    IndexBox cov;
    const bool has_cov = tab.cover(e, idx, cov);
    std::vector<double> u(static_cast<size_t>(m));
    ug.value(j, u.data());
    for (int q = 0; q < s.samples_per_box; ++q) {
      Eigen::VectorXd x0(n);
      const bool corner = q % 10 == 0;
      for (int i = 0; i < n; ++i) {
        const Interval c = g.cell(i, idx[i]);
        // Real cell bounds (without the quantizer slack) as the extreme points.
        const double clo = g.origin()[i] + static_cast<double>(idx[i]) * g.eta()[i];
        const double chi = clo + g.eta()[i];
        (void)c;
        x0[i] = corner ? ((rng() & 1u) ? clo : chi) : clo + unit(rng) * (chi - clo);
      }
      const int mode = static_cast<int>(rng() % 3);
      const std::uint64_t v1 = rng(), v2 = rng();
      const int switch_at = static_cast<int>(rng() % static_cast<std::uint64_t>(s.substeps));
      auto vertex = [&](std::uint64_t bits) {
        Eigen::VectorXd w(n);
        for (int i = 0; i < n; ++i) w[i] = ((bits >> i) & 1u) ? s.w[i] : -s.w[i];
        return w;
      };
      auto wfun = [&](int sub) -> Eigen::VectorXd {
        if (mode == 0) {
          Eigen::VectorXd w(n);
          for (int i = 0; i < n; ++i) w[i] = s.w[i] * (2 * unit(rng) - 1);
          return w;
        }
        if (mode == 1) return vertex(v1);
        return sub < switch_at ? vertex(v1) : vertex(v2);
      };
      const Eigen::VectorXd x1 = integrate_period(f, x0, u.data(), s.tau, s.substeps, wfun);
      ++r.samples;
      bool out = false;
      for (int i = 0; i < n; ++i) {
        const double d = std::max(lo[i] - x1[i], x1[i] - hi[i]);
        if (d > 0) {
          out = true;
          r.worst = std::max(r.worst, d / g.eta()[i]);
        }
      }
      if (out) ++r.escapes;
      if (has_cov && s.shrink == 0.0) {
        for (int i = 0; i < n; ++i) {
          const std::int64_t qi = g.index(i, x1[i]);
          if (qi < cov.lo[i] || qi > cov.hi[i]) {
            ++r.cover_escapes;
            break;
          }
        }
      }
    }
  }
  return r;
}

}  // namespace marsyn::abcd::testing
