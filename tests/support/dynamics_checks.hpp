#pragma once
// Checks every dynamics model must pass: AD Jacobians agree with central finite differences,
// interval evaluation over random boxes encloses point evaluations at random points of the box,
// and interval Jacobians (DualI) enclose point Jacobians.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "marsyn/dynamics.hpp"
#include "marsyn/sampled_map.hpp"

namespace marsyn::testing {

struct SampleBox {
  std::vector<double> lo, hi;  // states then inputs
};

inline void expect_ad_matches_finite_differences(const Dynamics& f, const SampleBox& where, int samples = 200) {
  const int n = f.state_dim(), m = f.input_dim();
  std::mt19937_64 rng(7);
  for (int s = 0; s < samples; ++s) {
    std::vector<double> z(n + m);
    for (int i = 0; i < n + m; ++i)
      z[i] = std::uniform_real_distribution<double>(where.lo[i], where.hi[i])(rng);
    std::vector<DualD> xd(n), ud(m), dd(n);
    for (int i = 0; i < n; ++i) xd[i] = DualD::variable(z[i], i, n + m);
    for (int j = 0; j < m; ++j) ud[j] = DualD::variable(z[n + j], n + j, n + m);
    f.field(xd.data(), ud.data(), dd.data());
    for (int j = 0; j < n + m; ++j) {
      const double h = 1e-6 * std::max(1.0, std::abs(z[j]));
      auto zp = z, zm = z;
      zp[j] += h;
      zm[j] -= h;
      std::vector<double> fp(n), fm(n);
      f.field(zp.data(), zp.data() + n, fp.data());
      f.field(zm.data(), zm.data() + n, fm.data());
      for (int i = 0; i < n; ++i) {
        const double fd = (fp[i] - fm[i]) / (2 * h);
        EXPECT_NEAR(dd[i].derivative(j), fd, 1e-5 * std::max(1.0, std::abs(fd)))
            << "d f" << i << " / d z" << j << " at sample " << s;
      }
    }
    // The value part of the dual evaluation is the plain evaluation.
    std::vector<double> plain(n);
    f.field(z.data(), z.data() + n, plain.data());
    for (int i = 0; i < n; ++i) EXPECT_DOUBLE_EQ(dd[i].v, plain[i]);
  }
}

// Random sub-boxes of `where`, random points inside each: f(point) in F(box), J(point) in J(box).
inline void expect_interval_encloses_points(const Dynamics& f, const SampleBox& where, int boxes = 300,
                                            int points = 100) {
  const int n = f.state_dim(), m = f.input_dim();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int b = 0; b < boxes; ++b) {
    std::vector<double> lo(n + m), hi(n + m);
    for (int i = 0; i < n + m; ++i) {
      const double a = where.lo[i] + unit(rng) * (where.hi[i] - where.lo[i]);
      const double w = unit(rng) * unit(rng) * (where.hi[i] - where.lo[i]) * 0.3;
      lo[i] = a;
      hi[i] = std::min(where.hi[i], a + w);
    }
    std::vector<Interval> xi(n), ui(m), fi(n);
    std::vector<DualI> xdi(n), udi(m), fdi(n);
    for (int i = 0; i < n; ++i) {
      xi[i] = Interval(lo[i], hi[i]);
      xdi[i] = DualI::variable(xi[i], i, n + m);
    }
    for (int j = 0; j < m; ++j) {
      ui[j] = Interval(lo[n + j], hi[n + j]);
      udi[j] = DualI::variable(ui[j], n + j, n + m);
    }
    f.field(xi.data(), ui.data(), fi.data());
    f.field(xdi.data(), udi.data(), fdi.data());
    for (int p = 0; p < points; ++p) {
      std::vector<double> z(n + m);
      for (int i = 0; i < n + m; ++i) {
        // Corners are where enclosures tend to break: pick them a third of the time.
        const double r = unit(rng);
        z[i] = r < 0.15 ? lo[i] : r < 0.3 ? hi[i] : lo[i] + unit(rng) * (hi[i] - lo[i]);
      }
      std::vector<double> fz(n);
      f.field(z.data(), z.data() + n, fz.data());
      std::vector<DualD> xd(n), ud(m), dd(n);
      for (int i = 0; i < n; ++i) xd[i] = DualD::variable(z[i], i, n + m);
      for (int j = 0; j < m; ++j) ud[j] = DualD::variable(z[n + j], n + j, n + m);
      f.field(xd.data(), ud.data(), dd.data());
      for (int i = 0; i < n; ++i) {
        ASSERT_LE(fi[i].lower(), fz[i]) << "component " << i << " box " << b;
        ASSERT_GE(fi[i].upper(), fz[i]) << "component " << i << " box " << b;
        for (int j = 0; j < n + m; ++j) {
          const Interval J = fdi[i].derivative(j);
          ASSERT_LE(J.lower(), dd[i].derivative(j)) << "d f" << i << "/dz" << j << " box " << b;
          ASSERT_GE(J.upper(), dd[i].derivative(j)) << "d f" << i << "/dz" << j << " box " << b;
        }
      }
    }
  }
}

// Translating the state along field_independent_of() coordinates leaves f unchanged.
inline void expect_declared_independence(const Dynamics& f, const SampleBox& where) {
  const int n = f.state_dim();
  const auto indep = f.field_independent_of();
  ASSERT_EQ(static_cast<int>(indep.size()), n);
  std::mt19937_64 rng(3);
  for (int s = 0; s < 100; ++s) {
    std::vector<double> z(n + f.input_dim());
    for (size_t i = 0; i < z.size(); ++i)
      z[i] = std::uniform_real_distribution<double>(where.lo[i], where.hi[i])(rng);
    std::vector<double> f0(n), f1(n);
    f.field(z.data(), z.data() + n, f0.data());
    auto shifted = z;
    for (int i = 0; i < n; ++i)
      if (indep[i]) shifted[i] += 3.7;
    f.field(shifted.data(), shifted.data() + n, f1.data());
    for (int i = 0; i < n; ++i) EXPECT_DOUBLE_EQ(f0[i], f1[i]);
  }
}

// A coordinate declared periodic() shifts by whole turns without changing f or any footprint
// (up to the rounding of sin and cos at the larger argument).
inline void expect_declared_periodicity(const Dynamics& f, const SampleBox& where) {
  const int n = f.state_dim();
  const auto periodic = f.periodic();
  ASSERT_EQ(static_cast<int>(periodic.size()), n);
  const double turn = 6.283185307179586;
  std::mt19937_64 rng(5);
  for (int s = 0; s < 100; ++s) {
    std::vector<double> z(n + f.input_dim());
    for (size_t i = 0; i < z.size(); ++i) z[i] = std::uniform_real_distribution<double>(where.lo[i], where.hi[i])(rng);
    std::vector<double> f0(n), f1(n);
    f.field(z.data(), z.data() + n, f0.data());
    for (int i = 0; i < n; ++i) {
      if (!periodic[i]) continue;
      for (double turns : {-3.0, -1.0, 1.0, 2.0}) {
        auto shifted = z;
        shifted[i] += turns * turn;
        f.field(shifted.data(), shifted.data() + n, f1.data());
        for (int j = 0; j < n; ++j) EXPECT_NEAR(f0[j], f1[j], 1e-9 * (1 + std::abs(f0[j]))) << "f_" << j << " at x_" << i << " + " << turns << " turns";
        for (int fp = 0; fp < static_cast<int>(f.footprints().size()); ++fp) {
          double p0[3] = {0, 0, 0}, p1[3] = {0, 0, 0};
          f.footprint(fp, z.data(), p0);
          f.footprint(fp, shifted.data(), p1);
          for (int c = 0; c < 3; ++c) EXPECT_NEAR(p0[c], p1[c], 1e-9 * (1 + std::abs(p0[c]))) << "footprint " << fp;
        }
      }
    }
  }
}

}  // namespace marsyn::testing
