#include <gtest/gtest.h>

#include "double_integrator.hpp"
#include "dynamics_checks.hpp"
#include "marsyn/sampled_map.hpp"

using marsyn::models::DoubleIntegrator;

TEST(DoubleIntegrator, Rk4IsExactForConstantAcceleration) {
  DoubleIntegrator f;
  const double x0[2] = {8.0, -0.5}, u[1] = {1.5}, t = 0.1;
  double x1[2];
  marsyn::rk4_step<double>(f, x0, u, nullptr, t, 1, x1);
  EXPECT_NEAR(x1[0], 8.0 - 0.05 + 0.5 * 1.5 * 0.01, 1e-15);
  EXPECT_NEAR(x1[1], -0.5 + 0.15, 1e-15);
}

const marsyn::testing::SampleBox kWhere{{3, -3, -3}, {9, 2, 3}};
TEST(DoubleIntegrator, JacobiansMatchFiniteDifferences) {
  marsyn::testing::expect_ad_matches_finite_differences(DoubleIntegrator{}, kWhere);
}
TEST(DoubleIntegrator, IntervalsEnclosePoints) {
  marsyn::testing::expect_interval_encloses_points(DoubleIntegrator{}, kWhere);
}
TEST(DoubleIntegrator, DeclaredIndependenceHolds) {
  marsyn::testing::expect_declared_independence(DoubleIntegrator{}, kWhere);
}
