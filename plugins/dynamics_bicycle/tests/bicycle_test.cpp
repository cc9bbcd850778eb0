#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "bicycle.hpp"
#include "dynamics_checks.hpp"
#include "model_extra_checks.hpp"
#include "marsyn/sampled_map.hpp"

using marsyn::models::Bicycle;

TEST(Bicycle, FieldMatchesHandDerivedValues) {
  Bicycle f;  // wheelbase 0.5
  const double x[5] = {1.0, 2.0, M_PI / 6, 2.0, M_PI / 4}, u[2] = {0.3, -0.2};
  double dx[5];
  f.field(x, u, dx);
  EXPECT_NEAR(dx[0], std::sqrt(3.0), 1e-15);  // 2 cos(pi/6)
  EXPECT_NEAR(dx[1], 1.0, 1e-15);             // 2 sin(pi/6)
  EXPECT_NEAR(dx[2], 4.0, 1e-14);             // 2 tan(pi/4) / 0.5
  EXPECT_DOUBLE_EQ(dx[3], 0.3);
  EXPECT_DOUBLE_EQ(dx[4], -0.2);
}

TEST(Bicycle, WheelbaseDividesTheTurnRate) {
  marsyn::Params p;
  p.set("wheelbase", 2.0);
  Bicycle f(p);
  EXPECT_DOUBLE_EQ(f.wheelbase(), 2.0);
  const double x[5] = {0.0, 0.0, 0.0, 3.0, -M_PI / 4}, u[2] = {0.0, 0.0};
  double dx[5];
  f.field(x, u, dx);
  EXPECT_NEAR(dx[2], -1.5, 1e-14);  // 3 tan(-pi/4) / 2
  EXPECT_DOUBLE_EQ(dx[0], 3.0);
  EXPECT_DOUBLE_EQ(dx[1], 0.0);
}

TEST(Bicycle, StraightAheadUnderConstantAcceleration) {
  // delta = 0, steering rate 0: theta stays, s(t) = v0 t + a t^2 / 2 along the heading (RK4 is
  // exact on this quadratic).
  Bicycle f;
  const double x0[5] = {0.5, -1.0, 0.4, 1.2, 0.0}, u[2] = {0.8, 0.0}, t = 0.5;
  double x1[5];
  marsyn::rk4_step<double>(f, x0, u, nullptr, t, 5, x1);
  const double s = x0[3] * t + 0.5 * u[0] * t * t;
  EXPECT_NEAR(x1[0], x0[0] + s * std::cos(x0[2]), 1e-14);
  EXPECT_NEAR(x1[1], x0[1] + s * std::sin(x0[2]), 1e-14);
  EXPECT_DOUBLE_EQ(x1[2], x0[2]);
  EXPECT_NEAR(x1[3], x0[3] + u[0] * t, 1e-14);
  EXPECT_DOUBLE_EQ(x1[4], 0.0);
}

TEST(Bicycle, ConstantSteeringDrivesTheCircleOfRadiusLOverTanDelta) {
  // Constant v and delta: a unicycle with turn rate w = v tan(delta) / L, i.e. the circle of
  // radius L / tan(delta): x = x0 + v/w (sin(th0 + w t) - sin th0), y = y0 - v/w (cos(th0 + w t) - cos th0).
  Bicycle f;
  const double x0[5] = {0.5, -1.0, 0.3, 1.7, -0.35}, u[2] = {0.0, 0.0}, t = 0.4;
  double x1[5];
  marsyn::rk4_step<double>(f, x0, u, nullptr, t, 20, x1);
  const double v = x0[3], w = v * std::tan(x0[4]) / 0.5;
  EXPECT_NEAR(x1[0], x0[0] + v / w * (std::sin(x0[2] + w * t) - std::sin(x0[2])), 1e-10);
  EXPECT_NEAR(x1[1], x0[1] - v / w * (std::cos(x0[2] + w * t) - std::cos(x0[2])), 1e-10);
  EXPECT_NEAR(x1[2], x0[2] + w * t, 1e-13);
  EXPECT_DOUBLE_EQ(x1[3], v);
  EXPECT_DOUBLE_EQ(x1[4], x0[4]);
  // After one full period 2 pi / |w| the bicycle is back where it started.
  double x[5] = {x0[0], x0[1], x0[2], x0[3], x0[4]};
  const double period = 2 * M_PI / std::abs(w);
  marsyn::rk4_step<double>(f, x, u, nullptr, period, 400, x);
  EXPECT_NEAR(x[0], x0[0], 1e-9);
  EXPECT_NEAR(x[1], x0[1], 1e-9);
}

TEST(Bicycle, ParametersAreValidated) {
  for (double bad : {0.0, -0.5, std::numeric_limits<double>::infinity(), std::nan("")}) {
    marsyn::Params p;
    p.set("wheelbase", bad);
    EXPECT_THROW(Bicycle{p}, marsyn::ParamError) << bad;
  }
  marsyn::Params text;
  text.set("wheelbase", std::string("long"));
  EXPECT_THROW(Bicycle{text}, marsyn::ParamError);
  const auto specs = Bicycle::param_specs();
  ASSERT_EQ(specs.size(), 1u);
  EXPECT_EQ(specs[0].name, "wheelbase");
  EXPECT_EQ(specs[0].type, marsyn::ParamType::Real);
  EXPECT_EQ(specs[0].default_value, "0.5");
  EXPECT_EQ(specs[0].range, "(0, inf)");
  EXPECT_DOUBLE_EQ(Bicycle{}.wheelbase(), std::stod(specs[0].default_value));  // the documented default is the one used
}

TEST(Bicycle, NamesAndDimensions) {
  Bicycle f;
  EXPECT_EQ(f.type(), "bicycle");
  EXPECT_EQ(f.state_dim(), 5);
  EXPECT_EQ(f.input_dim(), 2);
  EXPECT_EQ(f.state_names(), (std::vector<std::string>{"x", "y", "theta", "v", "delta"}));
  EXPECT_EQ(f.input_names(), (std::vector<std::string>{"accel", "steer_rate"}));
  EXPECT_EQ(f.field_independent_of(), (std::vector<bool>{true, true, false, false, false}));
}

// Steering within +-1.2 rad (tan up to 2.6), speeds forward and backward.
const marsyn::testing::SampleBox kWhere{{-5, -5, -4, -1.5, -1.2, -3, -1}, {5, 5, 4, 3, 1.2, 3, 1}};

TEST(Bicycle, JacobiansMatchFiniteDifferences) {
  marsyn::testing::expect_ad_matches_finite_differences(Bicycle{}, kWhere);
}
TEST(Bicycle, IntervalsEnclosePoints) { marsyn::testing::expect_interval_encloses_points(Bicycle{}, kWhere); }
TEST(Bicycle, FastIntervalsEnclosePoints) {
  marsyn::testing::expect_fast_interval_encloses_points(Bicycle{}, kWhere);
}
TEST(Bicycle, DeclaredIndependenceHolds) { marsyn::testing::expect_declared_independence(Bicycle{}, kWhere); }
TEST(Bicycle, HessiansMatchDifferencedJacobians) {
  marsyn::testing::expect_hessian_matches_differenced_jacobian(Bicycle{}, kWhere);
}

TEST(Bicycle, DiscreteJacobianMatchesFiniteDifferences) {
  Bicycle f;
  const double x[5] = {1, 2, 0.7, 1.3, 0.25}, u[2] = {0.4, -0.3};
  double A[25], B[10], next[5];
  marsyn::rk4_jacobians(f, x, u, 0.1, 4, next, A, B);
  for (int j = 0; j < 7; ++j) {
    double zp[7] = {x[0], x[1], x[2], x[3], x[4], u[0], u[1]};
    double zm[7] = {x[0], x[1], x[2], x[3], x[4], u[0], u[1]};
    zp[j] += 1e-6;
    zm[j] -= 1e-6;
    double fp[5], fm[5];
    marsyn::rk4_step<double>(f, zp, zp + 5, nullptr, 0.1, 4, fp);
    marsyn::rk4_step<double>(f, zm, zm + 5, nullptr, 0.1, 4, fm);
    for (int i = 0; i < 5; ++i) {
      const double fd = (fp[i] - fm[i]) / 2e-6;
      EXPECT_NEAR(j < 5 ? A[i * 5 + j] : B[i * 2 + (j - 5)], fd, 1e-7) << "d next" << i << " / dz" << j;
    }
  }
}

TEST(Bicycle, PluginLibraryCreatesTheModel) {
  marsyn::testing::LoadedLibrary lib(MARSYN_TEST_PLUGIN_FILE);
  ASSERT_NE(lib.handle, nullptr) << dlerror();
  ASSERT_NE(lib.manifest, nullptr);
  EXPECT_EQ(lib.manifest->api_version, MARSYN_PLUGIN_API_VERSION);
  EXPECT_EQ(lib.manifest->manifest_size, sizeof(marsyn_plugin_manifest));
  EXPECT_STREQ(lib.manifest->library, "marsyn_dynamics_bicycle");
  const marsyn_plugin_entry* e = lib.find("dynamics", "bicycle");
  ASSERT_NE(e, nullptr);
  const auto specs = e->param_specs();
  ASSERT_EQ(specs.size(), 1u);
  EXPECT_EQ(specs[0].name, "wheelbase");
  {
    marsyn::Params p;
    p.set("wheelbase", 0.8);
    auto dyn = lib.create(*e, p);
    EXPECT_EQ(dyn->type(), "bicycle");
    EXPECT_TRUE(dyn->has_second_order());
    marsyn::testing::expect_same_field(*dyn, Bicycle{p}, kWhere);
    p.set("wheelbase", -1.0);
    EXPECT_THROW(lib.create(*e, p), marsyn::ParamError);
  }
}

TEST(Bicycle, DeclaredPeriodicityHolds) { marsyn::testing::expect_declared_periodicity(Bicycle{}, kWhere); }
