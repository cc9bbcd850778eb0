#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "dynamics_checks.hpp"
#include "model_extra_checks.hpp"
#include "marsyn/sampled_map.hpp"
#include "planar_quadrotor.hpp"

using marsyn::models::PlanarQuadrotor;

TEST(PlanarQuadrotor, HoverIsAnEquilibrium) {
  PlanarQuadrotor f;
  const double x[6] = {1.5, 2.0, 0.0, 0.0, 0.0, 0.0}, u[2] = {9.81, 0.0};
  double dx[6];
  f.field(x, u, dx);
  for (double d : dx) EXPECT_EQ(d, 0.0);
}

TEST(PlanarQuadrotor, FieldMatchesHandDerivedValues) {
  // phi = pi/6, T = 12: vx' = -12 sin(pi/6) = -6, vz' = 12 cos(pi/6) - 9.81 = 6 sqrt(3) - 9.81.
  PlanarQuadrotor f;
  const double x[6] = {1.0, 2.0, M_PI / 6, 0.3, -0.2, 0.7}, u[2] = {12.0, 0.5};
  double dx[6];
  f.field(x, u, dx);
  EXPECT_DOUBLE_EQ(dx[0], 0.3);
  EXPECT_DOUBLE_EQ(dx[1], -0.2);
  EXPECT_DOUBLE_EQ(dx[2], 0.7);
  EXPECT_NEAR(dx[3], -6.0, 1e-14);
  EXPECT_NEAR(dx[4], 6.0 * std::sqrt(3.0) - 9.81, 1e-14);
  EXPECT_NEAR(dx[4], 0.5823048454132635, 1e-13);
  EXPECT_DOUBLE_EQ(dx[5], 0.5);
}

TEST(PlanarQuadrotor, PositivePitchTiltsTheThrustTowardMinusX) {
  PlanarQuadrotor f;
  const double x[6] = {0, 0, M_PI / 2, 0, 0, 0}, u[2] = {5.0, 0.0};
  double dx[6];
  f.field(x, u, dx);
  EXPECT_NEAR(dx[3], -5.0, 1e-15);
  EXPECT_NEAR(dx[4], -9.81, 1e-14);  // all thrust horizontal: falls with g
}

TEST(PlanarQuadrotor, GravityParameterReachesTheField) {
  marsyn::Params p;
  p.set("gravity", 1.62);
  PlanarQuadrotor f(p);
  EXPECT_DOUBLE_EQ(f.gravity(), 1.62);
  const double x[6] = {0, 0, 0, 0, 0, 0}, u[2] = {0.0, 0.0};
  double dx[6];
  f.field(x, u, dx);
  EXPECT_DOUBLE_EQ(dx[4], -1.62);
}

TEST(PlanarQuadrotor, FreeFallAndConstantTiltAreParabolas) {
  // omega = tau = 0: phi stays, the acceleration (-T sin phi, T cos phi - g) is constant and RK4
  // reproduces the parabola exactly (up to rounding).
  PlanarQuadrotor f;
  for (double T : {0.0, 11.0}) {
    const double x0[6] = {0.5, 3.0, -0.3, 1.2, 0.4, 0.0}, u[2] = {T, 0.0}, t = 0.6;
    double x1[6];
    marsyn::rk4_step<double>(f, x0, u, nullptr, t, 6, x1);
    const double ax = -T * std::sin(x0[2]), az = T * std::cos(x0[2]) - 9.81;
    EXPECT_NEAR(x1[0], x0[0] + x0[3] * t + 0.5 * ax * t * t, 1e-13) << T;
    EXPECT_NEAR(x1[1], x0[1] + x0[4] * t + 0.5 * az * t * t, 1e-13) << T;
    EXPECT_DOUBLE_EQ(x1[2], x0[2]);
    EXPECT_NEAR(x1[3], x0[3] + ax * t, 1e-13) << T;
    EXPECT_NEAR(x1[4], x0[4] + az * t, 1e-13) << T;
  }
}

TEST(PlanarQuadrotor, ConstantTorqueGivesAQuadraticPitch) {
  PlanarQuadrotor f;
  const double x0[6] = {0, 0, 0.1, 0, 0, -0.4}, u[2] = {9.81, 1.5}, t = 0.3;
  double x1[6];
  marsyn::rk4_step<double>(f, x0, u, nullptr, t, 3, x1);
  EXPECT_NEAR(x1[2], x0[2] + x0[5] * t + 0.5 * u[1] * t * t, 1e-14);
  EXPECT_NEAR(x1[5], x0[5] + u[1] * t, 1e-14);
}

TEST(PlanarQuadrotor, ParametersAreValidated) {
  for (double bad : {0.0, -9.81, std::numeric_limits<double>::infinity(), std::nan("")}) {
    marsyn::Params p;
    p.set("gravity", bad);
    EXPECT_THROW(PlanarQuadrotor{p}, marsyn::ParamError) << bad;
  }
  marsyn::Params text;
  text.set("gravity", std::string("earth"));
  EXPECT_THROW(PlanarQuadrotor{text}, marsyn::ParamError);
  const auto specs = PlanarQuadrotor::param_specs();
  ASSERT_EQ(specs.size(), 1u);
  EXPECT_EQ(specs[0].name, "gravity");
  EXPECT_EQ(specs[0].type, marsyn::ParamType::Real);
  EXPECT_EQ(specs[0].range, "(0, inf)");
  EXPECT_DOUBLE_EQ(PlanarQuadrotor{}.gravity(), std::stod(specs[0].default_value));
}

TEST(PlanarQuadrotor, NamesAndDimensions) {
  PlanarQuadrotor f;
  EXPECT_EQ(f.type(), "planar_quadrotor");
  EXPECT_EQ(f.state_dim(), 6);
  EXPECT_EQ(f.input_dim(), 2);
  EXPECT_EQ(f.state_names(), (std::vector<std::string>{"x", "z", "phi", "vx", "vz", "omega"}));
  EXPECT_EQ(f.input_names(), (std::vector<std::string>{"thrust", "torque"}));
  EXPECT_EQ(f.field_independent_of(), (std::vector<bool>{true, true, false, false, false, false}));
}

const marsyn::testing::SampleBox kWhere{{-5, -1, -3.2, -3, -3, -4, 0, -5}, {5, 6, 3.2, 3, 3, 4, 20, 5}};

TEST(PlanarQuadrotor, JacobiansMatchFiniteDifferences) {
  marsyn::testing::expect_ad_matches_finite_differences(PlanarQuadrotor{}, kWhere);
}
TEST(PlanarQuadrotor, IntervalsEnclosePoints) {
  marsyn::testing::expect_interval_encloses_points(PlanarQuadrotor{}, kWhere);
}
TEST(PlanarQuadrotor, FastIntervalsEnclosePoints) {
  marsyn::testing::expect_fast_interval_encloses_points(PlanarQuadrotor{}, kWhere);
}
TEST(PlanarQuadrotor, DeclaredIndependenceHolds) {
  marsyn::testing::expect_declared_independence(PlanarQuadrotor{}, kWhere);
}
TEST(PlanarQuadrotor, HessiansMatchDifferencedJacobians) {
  marsyn::testing::expect_hessian_matches_differenced_jacobian(PlanarQuadrotor{}, kWhere);
}

TEST(PlanarQuadrotor, DiscreteJacobianMatchesFiniteDifferences) {
  PlanarQuadrotor f;
  const double x[6] = {1, 2, 0.4, -0.5, 0.3, 0.8}, u[2] = {10.5, -1.2};
  double A[36], B[12], next[6];
  marsyn::rk4_jacobians(f, x, u, 0.1, 4, next, A, B);
  for (int j = 0; j < 8; ++j) {
    double zp[8] = {x[0], x[1], x[2], x[3], x[4], x[5], u[0], u[1]};
    double zm[8] = {x[0], x[1], x[2], x[3], x[4], x[5], u[0], u[1]};
    zp[j] += 1e-6;
    zm[j] -= 1e-6;
    double fp[6], fm[6];
    marsyn::rk4_step<double>(f, zp, zp + 6, nullptr, 0.1, 4, fp);
    marsyn::rk4_step<double>(f, zm, zm + 6, nullptr, 0.1, 4, fm);
    for (int i = 0; i < 6; ++i) {
      const double fd = (fp[i] - fm[i]) / 2e-6;
      EXPECT_NEAR(j < 6 ? A[i * 6 + j] : B[i * 2 + (j - 6)], fd, 1e-7) << "d next" << i << " / dz" << j;
    }
  }
}

TEST(PlanarQuadrotor, PluginLibraryCreatesTheModel) {
  marsyn::testing::LoadedLibrary lib(MARSYN_TEST_PLUGIN_FILE);
  ASSERT_NE(lib.handle, nullptr) << dlerror();
  ASSERT_NE(lib.manifest, nullptr);
  EXPECT_EQ(lib.manifest->api_version, MARSYN_PLUGIN_API_VERSION);
  EXPECT_EQ(lib.manifest->manifest_size, sizeof(marsyn_plugin_manifest));
  EXPECT_STREQ(lib.manifest->library, "marsyn_dynamics_planar_quadrotor");
  const marsyn_plugin_entry* e = lib.find("dynamics", "planar_quadrotor");
  ASSERT_NE(e, nullptr);
  const auto specs = e->param_specs();
  ASSERT_EQ(specs.size(), 1u);
  EXPECT_EQ(specs[0].name, "gravity");
  {
    marsyn::Params p;
    p.set("gravity", 3.7);
    auto dyn = lib.create(*e, p);
    EXPECT_EQ(dyn->type(), "planar_quadrotor");
    EXPECT_TRUE(dyn->has_second_order());
    marsyn::testing::expect_same_field(*dyn, PlanarQuadrotor{p}, kWhere);
    p.set("gravity", -1.0);
    EXPECT_THROW(lib.create(*e, p), marsyn::ParamError);
  }
}

TEST(PlanarQuadrotor, DeclaredPeriodicityHolds) { marsyn::testing::expect_declared_periodicity(PlanarQuadrotor{}, kWhere); }
