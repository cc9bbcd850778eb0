#include <gtest/gtest.h>

#include <cmath>

#include "cartpole.hpp"
#include "dynamics_checks.hpp"
#include "marsyn/sampled_map.hpp"

using marsyn::models::CartPole;

TEST(CartPole, HangingDownAtRestIsAnEquilibrium) {
  CartPole f;
  const double x[4] = {2.0, 0.0, M_PI, 0.0}, u[1] = {0.0};
  double dx[4];
  f.field(x, u, dx);
  for (double d : dx) EXPECT_NEAR(d, 0.0, 1e-14);
}

TEST(CartPole, HorizontalPoleFallsWithGOverFourThirdsL) {
  // theta = pi/2, at rest, no force: theta'' = g / (l 4/3) = 9.8 / (2/3) = 14.7, z'' = 0.
  CartPole f;
  const double x[4] = {0.0, 0.3, M_PI / 2, 0.0}, u[1] = {0.0};
  double dx[4];
  f.field(x, u, dx);
  EXPECT_DOUBLE_EQ(dx[0], 0.3);
  EXPECT_NEAR(dx[1], 0.0, 1e-14);
  EXPECT_DOUBLE_EQ(dx[2], 0.0);
  EXPECT_NEAR(dx[3], 14.7, 1e-12);
}

TEST(CartPole, UprightPushedByForce) {
  // theta = 0, F = 1.1 (= mt): push = 1, theta'' = -1 / (0.5 (4/3 - 0.1/1.1)) = -1.6097560975...,
  // z'' = 1 - (0.05/1.1) theta'' = 1.0731707317...
  CartPole f;
  const double x[4] = {0.0, 0.0, 0.0, 0.0}, u[1] = {1.1};
  double dx[4];
  f.field(x, u, dx);
  EXPECT_NEAR(dx[3], -1.0 / (0.5 * (4.0 / 3.0 - 0.1 / 1.1)), 1e-14);
  EXPECT_NEAR(dx[3], -1.6097560975609757, 1e-12);
  EXPECT_NEAR(dx[1], 1.0731707317073171, 1e-12);
}

TEST(CartPole, TipIsBelowTheRailWhenHanging) {
  CartPole f;
  const double x[4] = {2.0, 0.0, M_PI, 0.0};
  double p[2];
  f.footprint(0, x, p);
  EXPECT_NEAR(p[0], 2.0, 1e-15);
  EXPECT_NEAR(p[1], 0.1, 1e-15);
  ASSERT_EQ(f.footprints().size(), 1u);
}

TEST(CartPole, ParametersAreValidated) {
  marsyn::Params p;
  p.set("pole_mass", -1.0);
  EXPECT_THROW(CartPole{p}, marsyn::ParamError);
}

const marsyn::testing::SampleBox kWhere{{-0.2, -2, 1.2, -5.4, -7}, {5.5, 4.4, 4.7, 5.3, 7}};

TEST(CartPole, JacobiansMatchFiniteDifferences) {
  marsyn::testing::expect_ad_matches_finite_differences(CartPole{}, kWhere);
}
TEST(CartPole, IntervalsEnclosePoints) { marsyn::testing::expect_interval_encloses_points(CartPole{}, kWhere); }
TEST(CartPole, DeclaredIndependenceHolds) { marsyn::testing::expect_declared_independence(CartPole{}, kWhere); }

TEST(CartPole, EnergyIsNearlyConservedWithoutForceOverOneSecond) {
  // Frictionless, unforced: RK4 with small steps keeps the total energy to ~1e-8.
  CartPole f;
  const double mc = 1.0, mp = 0.1, l = 0.5, g = 9.8;
  auto energy = [&](const double* x) {
    // Pole as a uniform rod (inertia about the centre m l^2 / 3), theta from upright.
    const double vx = x[1] + l * std::cos(x[2]) * x[3], vy = -l * std::sin(x[2]) * x[3];
    return 0.5 * mc * x[1] * x[1] + 0.5 * mp * (vx * vx + vy * vy) + 0.5 * (mp * l * l / 3) * x[3] * x[3] +
           mp * g * l * std::cos(x[2]);
  };
  double x[4] = {0.0, 0.2, M_PI - 0.8, 0.0}, u[1] = {0.0};
  const double e0 = energy(x);
  for (int k = 0; k < 10; ++k) marsyn::rk4_step<double>(f, x, u, nullptr, 0.1, 20, x);
  EXPECT_NEAR(energy(x), e0, 1e-7);
}

TEST(CartPole, DeclaredPeriodicityHolds) { marsyn::testing::expect_declared_periodicity(CartPole{}, kWhere); }
