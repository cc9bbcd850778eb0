#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>

#include "dynamics_checks.hpp"
#include "model_extra_checks.hpp"
#include "marsyn/sampled_map.hpp"
#include "quadrotor.hpp"

using marsyn::models::Quadrotor;

namespace {

using Mat3 = std::array<std::array<double, 3>, 3>;

Mat3 mul(const Mat3& a, const Mat3& b) {
  Mat3 c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[i][j] += a[i][k] * b[k][j];
  return c;
}

// Body-to-world rotation R = Rz(psi) Ry(theta) Rx(phi), built from the elementary rotations
// (independent of the closed form in quadrotor.hpp).
Mat3 rotation(double phi, double theta, double psi) {
  const Mat3 rx{{{1, 0, 0}, {0, std::cos(phi), -std::sin(phi)}, {0, std::sin(phi), std::cos(phi)}}};
  const Mat3 ry{{{std::cos(theta), 0, std::sin(theta)}, {0, 1, 0}, {-std::sin(theta), 0, std::cos(theta)}}};
  const Mat3 rz{{{std::cos(psi), -std::sin(psi), 0}, {std::sin(psi), std::cos(psi), 0}, {0, 0, 1}}};
  return mul(rz, mul(ry, rx));
}

}  // namespace

TEST(Quadrotor, HoverIsAnEquilibriumAtAnyYaw) {
  Quadrotor f;
  for (double psi : {0.0, 1.0, -2.5}) {
    const double x[12] = {1, 2, 3, 0, 0, psi, 0, 0, 0, 0, 0, 0}, u[4] = {9.81, 0, 0, 0};
    double dx[12];
    f.field(x, u, dx);
    for (int i = 0; i < 12; ++i) EXPECT_NEAR(dx[i], 0.0, 1e-15) << "component " << i << " yaw " << psi;
  }
}

TEST(Quadrotor, ThrustPointsAlongTheBodyZAxis) {
  // v' + g e3 = T R e3, with R from the elementary rotations; hand value for one point:
  // phi = pi/6, theta = pi/4, psi = pi/3, T = 10.
  Quadrotor f;
  const double phi = M_PI / 6, theta = M_PI / 4, psi = M_PI / 3, T = 10;
  const double x[12] = {0, 0, 0, phi, theta, psi, 0.1, 0.2, 0.3, 0, 0, 0}, u[4] = {T, 0, 0, 0};
  double dx[12];
  f.field(x, u, dx);
  const Mat3 R = rotation(phi, theta, psi);
  EXPECT_NEAR(dx[6], T * R[0][2], 1e-14);
  EXPECT_NEAR(dx[7], T * R[1][2], 1e-14);
  EXPECT_NEAR(dx[8] + 9.81, T * R[2][2], 1e-14);
  // By hand: R e3 = (c(pi/6) s(pi/4) c(pi/3) + s(pi/6) s(pi/3), c(pi/6) s(pi/4) s(pi/3) - s(pi/6) c(pi/3),
  // c(pi/6) c(pi/4)) = (sqrt6/8 + sqrt3/4, 3 sqrt2/8 - 1/4, sqrt6/4).
  EXPECT_NEAR(dx[6], 10 * (std::sqrt(6.0) / 8 + std::sqrt(3.0) / 4), 1e-13);
  EXPECT_NEAR(dx[7], 10 * (3 * std::sqrt(2.0) / 8 - 0.25), 1e-13);
  EXPECT_NEAR(dx[8], 10 * std::sqrt(6.0) / 4 - 9.81, 1e-13);
  EXPECT_DOUBLE_EQ(dx[0], 0.1);
  EXPECT_DOUBLE_EQ(dx[1], 0.2);
  EXPECT_DOUBLE_EQ(dx[2], 0.3);
}

TEST(Quadrotor, EulerRatesMapBackToTheBodyRates) {
  // (p, q, r) = W(phi, theta) (phi', theta', psi') with W = [[1, 0, -s th], [0, c phi, s phi c th],
  // [0, -s phi, c phi c th]]: the inverse of the kinematics in the field.
  Quadrotor f;
  const double phi = -0.7, theta = 0.9, psi = 2.0, p = 0.8, q = -1.3, r = 0.45;
  const double x[12] = {0, 0, 0, phi, theta, psi, 0, 0, 0, p, q, r}, u[4] = {9.81, 0, 0, 0};
  double dx[12];
  f.field(x, u, dx);
  const double sp = std::sin(phi), cp = std::cos(phi), st = std::sin(theta), ct = std::cos(theta);
  EXPECT_NEAR(dx[3] - st * dx[5], p, 1e-14);
  EXPECT_NEAR(cp * dx[4] + sp * ct * dx[5], q, 1e-14);
  EXPECT_NEAR(-sp * dx[4] + cp * ct * dx[5], r, 1e-14);
}

TEST(Quadrotor, PitchOnlyMotionIsThePlanarQuadrotor) {
  // phi = psi = 0, p = r = 0: x-z motion of the planar quadrotor with its pitch = -theta
  // (vx' = T sin theta, vz' = T cos theta - g, theta' = q, q' = torque_y).
  Quadrotor f;
  const double theta = 0.35, T = 11.0;
  const double x[12] = {0, 0, 0, 0, theta, 0, 0, 0, 0, 0, 0.6, 0}, u[4] = {T, 0, 2.5, 0};
  double dx[12];
  f.field(x, u, dx);
  EXPECT_NEAR(dx[6], T * std::sin(theta), 1e-14);
  EXPECT_NEAR(dx[7], 0.0, 1e-15);
  EXPECT_NEAR(dx[8], T * std::cos(theta) - 9.81, 1e-14);
  EXPECT_NEAR(dx[3], 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(dx[4], 0.6);
  EXPECT_NEAR(dx[5], 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(dx[10], 2.5);
}

TEST(Quadrotor, BodyRatesFollowEulersEquations) {
  // Ixx = 1, Iyy = 2, Izz = 2.5: p' = (2 - 2.5)/1 q r, q' = (2.5 - 1)/2 p r, r' = (1 - 2)/2.5 p q.
  marsyn::Params prm;
  prm.set("inertia_xx", 1.0);
  prm.set("inertia_yy", 2.0);
  prm.set("inertia_zz", 2.5);
  Quadrotor f(prm);
  const double x[12] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0.4, -1.0, 2.0}, u[4] = {9.81, 0.1, 0.2, 0.3};
  double dx[12];
  f.field(x, u, dx);
  EXPECT_NEAR(dx[9], -0.5 * (-1.0 * 2.0) + 0.1, 1e-15);
  EXPECT_NEAR(dx[10], 0.75 * (0.4 * 2.0) + 0.2, 1e-15);
  EXPECT_NEAR(dx[11], -0.4 * (0.4 * -1.0) + 0.3, 1e-15);
}

TEST(Quadrotor, TorqueFreeRotationConservesEnergyAndWorldAngularMomentum) {
  // No torque: the rotational energy (1/2) w' I w and the world-frame angular momentum R I w are
  // constant (wrong inertia signs or kinematics break one of them). Small rates keep theta away
  // from the gimbal lock over the second simulated.
  marsyn::Params prm;
  prm.set("inertia_xx", 1.0);
  prm.set("inertia_yy", 2.0);
  prm.set("inertia_zz", 2.5);
  Quadrotor f(prm);
  const double I[3] = {1.0, 2.0, 2.5};
  double x[12] = {0, 0, 0, 0.2, -0.1, 0.4, 0, 0, 0, 0.5, 0.3, -0.4};
  const double u[4] = {9.81, 0, 0, 0};
  auto energy = [&](const double* s) {
    return 0.5 * (I[0] * s[9] * s[9] + I[1] * s[10] * s[10] + I[2] * s[11] * s[11]);
  };
  auto momentum = [&](const double* s) {
    const Mat3 R = rotation(s[3], s[4], s[5]);
    const double Lb[3] = {I[0] * s[9], I[1] * s[10], I[2] * s[11]};
    std::array<double, 3> L{};
    for (int i = 0; i < 3; ++i) L[i] = R[i][0] * Lb[0] + R[i][1] * Lb[1] + R[i][2] * Lb[2];
    return L;
  };
  const double e0 = energy(x);
  const auto L0 = momentum(x);
  for (int k = 0; k < 10; ++k) marsyn::rk4_step<double>(f, x, u, nullptr, 0.1, 20, x);
  EXPECT_NEAR(energy(x), e0, 1e-9);
  const auto L1 = momentum(x);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(L1[i], L0[i], 1e-8) << "component " << i;
  EXPECT_GT(std::abs(x[9] - 0.5) + std::abs(x[10] - 0.3), 1e-3);  // the rates did change
}

TEST(Quadrotor, ParametersAreValidated) {
  const char* names[] = {"gravity", "inertia_xx", "inertia_yy", "inertia_zz"};
  for (const char* name : names)
    for (double bad : {0.0, -1.0, std::numeric_limits<double>::infinity(), std::nan("")}) {
      marsyn::Params p;
      p.set(name, bad);
      EXPECT_THROW(Quadrotor{p}, marsyn::ParamError) << name << " = " << bad;
    }
  // Not a rigid body: Izz > Ixx + Iyy.
  marsyn::Params flat;
  flat.set("inertia_xx", 1.0);
  flat.set("inertia_yy", 1.0);
  flat.set("inertia_zz", 2.5);
  EXPECT_THROW(Quadrotor{flat}, marsyn::ParamError);
  flat.set("inertia_zz", 2.0);  // a flat plate: the limit case is allowed
  EXPECT_NO_THROW(Quadrotor{flat});
  marsyn::Params text;
  text.set("gravity", std::string("earth"));
  EXPECT_THROW(Quadrotor{text}, marsyn::ParamError);
  const auto specs = Quadrotor::param_specs();
  ASSERT_EQ(specs.size(), 4u);
  Quadrotor d;
  EXPECT_DOUBLE_EQ(d.gravity(), std::stod(specs[0].default_value));
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(specs[1 + a].name, names[1 + a]);
    EXPECT_EQ(specs[1 + a].range, "(0, inf)");
    EXPECT_DOUBLE_EQ(d.inertia(a), std::stod(specs[1 + a].default_value));
  }
}

TEST(Quadrotor, NamesAndDimensions) {
  Quadrotor f;
  EXPECT_EQ(f.type(), "quadrotor");
  EXPECT_EQ(f.state_dim(), 12);
  EXPECT_EQ(f.input_dim(), 4);
  EXPECT_LE(f.state_dim() + f.input_dim(), marsyn::kMaxDual);
  EXPECT_EQ(f.state_names(),
            (std::vector<std::string>{"x", "y", "z", "phi", "theta", "psi", "vx", "vy", "vz", "p", "q", "r"}));
  EXPECT_EQ(f.input_names(), (std::vector<std::string>{"thrust", "torque_x", "torque_y", "torque_z"}));
  std::vector<bool> indep(12, false);
  indep[0] = indep[1] = indep[2] = true;
  EXPECT_EQ(f.field_independent_of(), indep);
}

// |phi|, |theta| <= 1.2 (away from the gimbal lock), any yaw; the default (Crazyflie) inertias.
const marsyn::testing::SampleBox kWhere{{-5, -5, -1, -1.2, -1.2, -3.2, -3, -3, -3, -4, -4, -4, 0, -20, -20, -20},
                                        {5, 5, 6, 1.2, 1.2, 3.2, 3, 3, 3, 4, 4, 4, 20, 20, 20, 20}};

TEST(Quadrotor, JacobiansMatchFiniteDifferences) {
  marsyn::testing::expect_ad_matches_finite_differences(Quadrotor{}, kWhere);
}
TEST(Quadrotor, IntervalsEnclosePoints) { marsyn::testing::expect_interval_encloses_points(Quadrotor{}, kWhere); }
TEST(Quadrotor, FastIntervalsEnclosePoints) {
  marsyn::testing::expect_fast_interval_encloses_points(Quadrotor{}, kWhere);
}
TEST(Quadrotor, DeclaredIndependenceHolds) { marsyn::testing::expect_declared_independence(Quadrotor{}, kWhere); }
TEST(Quadrotor, HessiansMatchDifferencedJacobians) {
  marsyn::testing::expect_hessian_matches_differenced_jacobian(Quadrotor{}, kWhere);
}

TEST(Quadrotor, DiscreteJacobianMatchesFiniteDifferences) {
  Quadrotor f;
  const double z0[16] = {1, 2, 3, 0.2, -0.3, 0.8, 0.5, -0.4, 0.1, 0.7, -0.6, 0.3, 10.2, 1.5, -2.0, 0.4};
  double A[144], B[48], next[12];
  marsyn::rk4_jacobians(f, z0, z0 + 12, 0.05, 4, next, A, B);
  for (int j = 0; j < 16; ++j) {
    double zp[16], zm[16];
    for (int i = 0; i < 16; ++i) zp[i] = zm[i] = z0[i];
    zp[j] += 1e-6;
    zm[j] -= 1e-6;
    double fp[12], fm[12];
    marsyn::rk4_step<double>(f, zp, zp + 12, nullptr, 0.05, 4, fp);
    marsyn::rk4_step<double>(f, zm, zm + 12, nullptr, 0.05, 4, fm);
    for (int i = 0; i < 12; ++i) {
      const double fd = (fp[i] - fm[i]) / 2e-6;
      EXPECT_NEAR(j < 12 ? A[i * 12 + j] : B[i * 4 + (j - 12)], fd, 1e-7) << "d next" << i << " / dz" << j;
    }
  }
}

TEST(Quadrotor, PluginLibraryCreatesTheModel) {
  marsyn::testing::LoadedLibrary lib(MARSYN_TEST_PLUGIN_FILE);
  ASSERT_NE(lib.handle, nullptr) << dlerror();
  ASSERT_NE(lib.manifest, nullptr);
  EXPECT_EQ(lib.manifest->api_version, MARSYN_PLUGIN_API_VERSION);
  EXPECT_EQ(lib.manifest->manifest_size, sizeof(marsyn_plugin_manifest));
  EXPECT_STREQ(lib.manifest->library, "marsyn_dynamics_quadrotor");
  const marsyn_plugin_entry* e = lib.find("dynamics", "quadrotor");
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->param_specs().size(), 4u);
  {
    marsyn::Params p;
    p.set("gravity", 3.7);
    p.set("inertia_zz", 3.0e-5);
    auto dyn = lib.create(*e, p);
    EXPECT_EQ(dyn->type(), "quadrotor");
    EXPECT_TRUE(dyn->has_second_order());
    marsyn::testing::expect_same_field(*dyn, Quadrotor{p}, kWhere);
    p.set("inertia_zz", 1.0);  // violates the triangle inequality
    EXPECT_THROW(lib.create(*e, p), marsyn::ParamError);
  }
}

TEST(Quadrotor, DeclaredPeriodicityHolds) { marsyn::testing::expect_declared_periodicity(Quadrotor{}, kWhere); }
