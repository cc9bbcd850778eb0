#include <gtest/gtest.h>

#include <cmath>

#include "dynamics_checks.hpp"
#include "marsyn/sampled_map.hpp"
#include "pendulum.hpp"

using marsyn::models::Pendulum;

TEST(Pendulum, FieldMatchesHandDerivedValues) {
  Pendulum f;
  const double x[2] = {M_PI / 2, 1.0}, u[1] = {1.0};
  double dx[2];
  f.field(x, u, dx);
  EXPECT_DOUBLE_EQ(dx[0], 1.0);
  EXPECT_NEAR(dx[1], -0.8, 1e-15);  // -sin(pi/2) + 1/5
}

TEST(Pendulum, SmallOscillationHasPeriodTwoPi) {
  Pendulum f;
  double x[2] = {1e-3, 0.0}, u[1] = {0.0};
  const int steps = 628;  // 2 pi / 0.01 (about one period)
  for (int k = 0; k < steps; ++k) marsyn::rk4_step<double>(f, x, u, nullptr, 0.01, 1, x);
  EXPECT_NEAR(x[0], 1e-3 * std::cos(6.28), 1e-8);
}

const marsyn::testing::SampleBox kWhere{{-1, -3, -5}, {4.5, 3, 5}};
TEST(Pendulum, JacobiansMatchFiniteDifferences) {
  marsyn::testing::expect_ad_matches_finite_differences(Pendulum{}, kWhere);
}
TEST(Pendulum, IntervalsEnclosePoints) { marsyn::testing::expect_interval_encloses_points(Pendulum{}, kWhere); }
TEST(Pendulum, DeclaredPeriodicityHolds) { marsyn::testing::expect_declared_periodicity(Pendulum{}, kWhere); }
