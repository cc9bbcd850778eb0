#include <gtest/gtest.h>

#include <cmath>

#include "dynamics_checks.hpp"
#include "marsyn/sampled_map.hpp"
#include "unicycle.hpp"

using marsyn::models::Unicycle;

TEST(Unicycle, FieldMatchesHandDerivedValues) {
  Unicycle f;
  const double x[3] = {1.0, 2.0, M_PI / 3}, u[2] = {2.0, 0.5};
  double dx[3];
  f.field(x, u, dx);
  EXPECT_NEAR(dx[0], 1.0, 1e-15);               // 2 cos(pi/3)
  EXPECT_NEAR(dx[1], std::sqrt(3.0), 1e-15);    // 2 sin(pi/3)
  EXPECT_DOUBLE_EQ(dx[2], 0.5);
}

TEST(Unicycle, Rk4MatchesClosedFormArc) {
  // Constant (v, w): x = x0 + v/w (sin(th0 + w t) - sin th0), y = y0 - v/w (cos(th0 + w t) - cos th0).
  Unicycle f;
  const double x0[3] = {0.5, -1.0, 0.3}, u[2] = {1.7, -0.9}, t = 0.1;
  double x1[3];
  marsyn::rk4_step<double>(f, x0, u, nullptr, t, 10, x1);
  const double v = u[0], w = u[1];
  EXPECT_NEAR(x1[0], x0[0] + v / w * (std::sin(x0[2] + w * t) - std::sin(x0[2])), 1e-12);
  EXPECT_NEAR(x1[1], x0[1] - v / w * (std::cos(x0[2] + w * t) - std::cos(x0[2])), 1e-12);
  EXPECT_NEAR(x1[2], x0[2] + w * t, 1e-14);
}

TEST(Unicycle, DisturbanceEntersAdditively) {
  Unicycle f;
  const double x0[3] = {0, 0, 0}, u[2] = {0, 0}, w[3] = {0.1, -0.2, 0.05};
  double x1[3];
  marsyn::rk4_step<double>(f, x0, u, w, 0.1, 4, x1);
  EXPECT_NEAR(x1[0], 0.01, 1e-15);
  EXPECT_NEAR(x1[1], -0.02, 1e-15);
  EXPECT_NEAR(x1[2], 0.005, 1e-15);
}

const marsyn::testing::SampleBox kWhere{{-1, -1, -4, -2.4, -3}, {11, 11, 4, 2.4, 3}};

TEST(Unicycle, JacobiansMatchFiniteDifferences) {
  marsyn::testing::expect_ad_matches_finite_differences(Unicycle{}, kWhere);
}
TEST(Unicycle, IntervalsEnclosePoints) { marsyn::testing::expect_interval_encloses_points(Unicycle{}, kWhere); }
TEST(Unicycle, DeclaredIndependenceHolds) { marsyn::testing::expect_declared_independence(Unicycle{}, kWhere); }

TEST(Unicycle, DiscreteJacobianMatchesFiniteDifferences) {
  Unicycle f;
  const double x[3] = {1, 2, 0.7}, u[2] = {1.5, 0.4};
  double A[9], B[6], next[3];
  marsyn::rk4_jacobians(f, x, u, 0.1, 4, next, A, B);
  for (int j = 0; j < 5; ++j) {
    double zp[5] = {x[0], x[1], x[2], u[0], u[1]}, zm[5] = {x[0], x[1], x[2], u[0], u[1]};
    zp[j] += 1e-6;
    zm[j] -= 1e-6;
    double fp[3], fm[3];
    marsyn::rk4_step<double>(f, zp, zp + 3, nullptr, 0.1, 4, fp);
    marsyn::rk4_step<double>(f, zm, zm + 3, nullptr, 0.1, 4, fm);
    for (int i = 0; i < 3; ++i) {
      const double fd = (fp[i] - fm[i]) / 2e-6;
      EXPECT_NEAR(j < 3 ? A[i * 3 + j] : B[i * 2 + (j - 3)], fd, 1e-7);
    }
  }
}

// The dual overload (one sine and cosine, no temporaries) must give what the generic template
// gives: the planner's Jacobians and every tracker's read it.
TEST(Unicycle, DualFieldEqualsTheGenericForm) {
  Unicycle f;
  for (int t = 0; t < 200; ++t) {
    const double th = -7.0 + 14.0 * t / 199.0, v = -2.4 + 4.8 * ((t * 37) % 199) / 198.0, w = 0.3 - 0.01 * t;
    marsyn::DualD x[3], u[2], fast[3], generic[3];
    const double vals[5] = {0.5 * t, -0.25 * t, th, v, w};
    for (int i = 0; i < 3; ++i) x[i] = marsyn::DualD::variable(vals[i], i, 5);
    for (int j = 0; j < 2; ++j) u[j] = marsyn::DualD::variable(vals[3 + j], 3 + j, 5);
    f.vector_field(x, u, fast);
    f.vector_field<marsyn::DualD>(x, u, generic);
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(fast[i].v, generic[i].v);
      EXPECT_EQ(fast[i].n, generic[i].n);
      for (int j = 0; j < 5; ++j) EXPECT_EQ(fast[i].derivative(j), generic[i].derivative(j)) << i << " " << j;
    }
  }
}

TEST(Unicycle, DeclaredPeriodicityHolds) { marsyn::testing::expect_declared_periodicity(Unicycle{}, kWhere); }
