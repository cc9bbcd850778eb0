// iLQR on a linear-quadratic problem must reproduce the LQ optimum, here computed independently
// by solving the batch least-squares problem over all inputs.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "altro_solver.hpp"
#include "rk4.hpp"
#include "dynamics_double_integrator/src/double_integrator.hpp"
#include "marsyn/sampled_map.hpp"

using namespace marsyn;

namespace {

Problem integrator_problem(int T) {
  Problem p;
  AgentSpec a;
  a.name = "car";
  a.dynamics = std::make_shared<models::DoubleIntegrator>();
  a.x0 = Eigen::Vector2d(2.0, -1.0);
  a.input_bounds = {Eigen::VectorXd::Constant(1, -1e6), Eigen::VectorXd::Constant(1, 1e6)};
  a.state_bounds = {Eigen::Vector2d(-1e6, -1e6), Eigen::Vector2d(1e6, 1e6)};
  a.goal = {Eigen::Vector2d(-1e3, -1e3), Eigen::Vector2d(1e3, 1e3)};  // centre 0, never active
  a.tube.eps = Eigen::Vector2d::Zero();
  a.workspace.index = {0, -1};
  p.agents.push_back(a);
  p.tau = 0.1;
  p.horizon = T;
  return p;
}

PlanningProblem planning(const Problem& p) {
  const auto& a = p.agents[0];
  PlanningProblem pp;
  pp.problem = &p;
  pp.x0 = a.x0;
  pp.input_bounds = a.input_bounds;
  pp.state_bounds = a.state_bounds;
  pp.goal = a.goal;
  pp.horizon = p.horizon;
  return pp;
}

}  // namespace

TEST(Ilqr, MatchesTheLinearQuadraticOptimum) {
  const int T = 40;
  const Problem p = integrator_problem(T);
  altro::Options o;
  o.q_track = 0.7;
  o.r_input = 0.05;
  o.q_terminal = 20.0;
  o.bend = 0.0;
  o.reg_initial = o.reg_min = 0.0;
  o.cost_tolerance = o.cost_tolerance_intermediate = 1e-14;
  const auto r = altro::solve(planning(p), {}, o);
  ASSERT_EQ(r.status, PlannerStatus::ExactSolution) << r.message;

  // Batch: x_k = Phi_k x0 + sum_j Gamma_kj u_j; minimise the same cost in U directly.
  Eigen::Matrix2d A;
  Eigen::Vector2d B;
  {
    double x[2] = {0, 0}, u[1] = {0}, Ar[4], Br[2];
    rk4_jacobians(*p.agents[0].dynamics, x, u, p.tau, p.rk4_substeps, nullptr, Ar, Br);
    A << Ar[0], Ar[1], Ar[2], Ar[3];
    B << Br[0], Br[1];
  }
  const Eigen::Vector2d x0 = p.agents[0].x0;
  Eigen::MatrixXd H = o.r_input * Eigen::MatrixXd::Identity(T, T);
  Eigen::VectorXd h = Eigen::VectorXd::Zero(T);
  Eigen::Matrix2d Phi = Eigen::Matrix2d::Identity();
  Eigen::MatrixXd Gam = Eigen::MatrixXd::Zero(2, T);
  for (int k = 1; k <= T; ++k) {
    Gam = (A * Gam).eval();
    Gam.col(k - 1) = B;
    Phi = A * Phi;
    const double q = k == T ? o.q_terminal : o.q_track;
    const Eigen::Vector2d ref = x0 * (1.0 - double(k) / T) * (k == T ? 0.0 : 1.0);
    H += q * Gam.transpose() * Gam;
    h += q * Gam.transpose() * (Phi * x0 - ref);
  }
  const Eigen::VectorXd U = -H.ldlt().solve(h);
  for (int k = 0; k < T; ++k) EXPECT_NEAR(r.plan.u[k][0], U[k], 1e-6) << "k = " << k;
}

#include "dynamics_bicycle/src/bicycle.hpp"
#include "dynamics_cartpole/src/cartpole.hpp"
#include "dynamics_planar_quadrotor/src/planar_quadrotor.hpp"
#include "dynamics_unicycle/src/unicycle.hpp"

TEST(Jacobians, StagedRk4DerivativeEqualsForwardAd) {
  const models::CartPole crane;
  const models::Unicycle uni;
  const std::vector<std::pair<const Dynamics*, std::vector<double>>> cases = {
      {&crane, {0.3, -0.7, 2.9, 1.3, 4.2}}, {&uni, {1.0, -2.0, 0.7, 1.5, -0.8}}};
  for (const auto& [dyn, xu] : cases) {
    const int n = dyn->state_dim(), m = dyn->input_dim();
    std::vector<double> A1(n * n), B1(n * m), A2(n * n), B2(n * m);
    rk4_jacobians(*dyn, xu.data(), xu.data() + n, 0.1, 4, nullptr, A1.data(), B1.data());
    altro::rk4_jacobians_staged(*dyn, xu.data(), xu.data() + n, 0.1, 4, A2.data(), B2.data());
    for (int i = 0; i < n * n; ++i) EXPECT_NEAR(A1[i], A2[i], 1e-12) << dyn->type() << " A " << i;
    for (int i = 0; i < n * m; ++i) EXPECT_NEAR(B1[i], B2[i], 1e-12) << dyn->type() << " B " << i;
  }
}

// With the mask of the coordinates the field reads (the unicycle ignores its position, so RK4's
// stages 2 and 3 share one evaluation), the derivative is the same, bit for bit.
TEST(Jacobians, StagedRk4WithTheFieldsReadsIsTheSame) {
  const models::CartPole crane;
  const models::Unicycle uni;
  EXPECT_EQ(altro::field_reads(uni), 4u);
  const std::vector<std::pair<const Dynamics*, std::vector<double>>> cases = {
      {&crane, {0.3, -0.7, 2.9, 1.3, 4.2}}, {&uni, {1.0, -2.0, 0.7, 1.5, -0.8}}, {&uni, {3.0, 0.5, -2.1, -0.4, 2.2}}};
  for (const auto& [dyn, xu] : cases)
    for (int substeps : {1, 4}) {
      const int n = dyn->state_dim(), m = dyn->input_dim();
      std::vector<double> A1(n * n), B1(n * m), A2(n * n), B2(n * m);
      altro::rk4_jacobians_staged(*dyn, xu.data(), xu.data() + n, 0.1, substeps, A1.data(), B1.data());
      altro::rk4_jacobians_staged(*dyn, xu.data(), xu.data() + n, 0.1, substeps, A2.data(), B2.data(),
                                  altro::field_reads(*dyn));
      for (int i = 0; i < n * n; ++i) EXPECT_EQ(A1[i], A2[i]) << dyn->type() << " A " << i;
      for (int i = 0; i < n * m; ++i) EXPECT_EQ(B1[i], B2[i]) << dyn->type() << " B " << i;
    }
}

// The staged sweep keeps its dual arguments per thread between calls (seeded when the model's
// width changes): calls that alternate between models of different sizes, through the generic
// sweep (bicycle 5 + 2, planar quadrotor 6 + 2) and the unrolled ones, must each give what a
// first call on that model gives, and forward AD's derivative.
TEST(Jacobians, StagedRk4AlternatingModelsKeepTheirOwnDerivatives) {
  const models::Bicycle bike;
  const models::PlanarQuadrotor quad;
  const models::CartPole crane;
  const models::Unicycle uni;
  struct Case {
    const Dynamics* dyn;
    std::vector<double> xu;
    std::vector<double> A, B;  // the first call's
  };
  std::vector<Case> cases = {{&bike, {0.4, -1.1, 0.3, 1.2, -0.2, 0.8, 0.1}, {}, {}},
                             {&quad, {0.1, 0.2, -0.3, 0.4, 0.05, -0.6, 5.1, 4.7}, {}, {}},
                             {&crane, {0.3, -0.7, 2.9, 1.3, 4.2}, {}, {}},
                             {&uni, {1.0, -2.0, 0.7, 1.5, -0.8}, {}, {}}};
  for (int round = 0; round < 3; ++round)
    for (auto& c : cases) {
      const int n = c.dyn->state_dim(), m = c.dyn->input_dim();
      std::vector<double> A(n * n), B(n * m), A1(n * n), B1(n * m);
      altro::rk4_jacobians_staged(*c.dyn, c.xu.data(), c.xu.data() + n, 0.1, 4, A.data(), B.data(),
                                  altro::field_reads(*c.dyn));
      if (round == 0) {
        rk4_jacobians(*c.dyn, c.xu.data(), c.xu.data() + n, 0.1, 4, nullptr, A1.data(), B1.data());
        for (int i = 0; i < n * n; ++i) EXPECT_NEAR(A1[i], A[i], 1e-12) << c.dyn->type() << " A " << i;
        for (int i = 0; i < n * m; ++i) EXPECT_NEAR(B1[i], B[i], 1e-12) << c.dyn->type() << " B " << i;
        c.A = A;
        c.B = B;
        continue;
      }
      EXPECT_EQ(c.A, A) << c.dyn->type() << " round " << round;
      EXPECT_EQ(c.B, B) << c.dyn->type() << " round " << round;
    }
}

// The rollouts' RK4 with the last field evaluation kept (KeptField) must give rk4_step's states
// bit for bit, over whole periods and partial runs of substeps, for models that read all or part
// of their state; a mask that leaves out a coordinate the field reads must not (the test can fail).
TEST(Jacobians, KeptFieldStepIsTheRk4StepBitForBit) {
  const models::Bicycle bike;
  const models::PlanarQuadrotor quad;
  const models::CartPole crane;
  const models::Unicycle uni;
  const std::vector<std::pair<const Dynamics*, std::vector<double>>> cases = {
      {&bike, {0.4, -1.1, 0.3, 1.2, -0.2, 0.8, 0.1}},
      {&quad, {0.1, 0.2, -0.3, 0.4, 0.05, -0.6, 5.1, 4.7}},
      {&crane, {0.3, -0.7, 2.9, 1.3, 4.2}},
      {&uni, {1.0, -2.0, 0.7, 1.5, -0.8}}};
  for (const auto& [dyn, xu] : cases)
    for (int substeps : {1, 2, 4, 6})
      for (int steps : {-1, 1, substeps / 2}) {
        const int n = dyn->state_dim();
        std::vector<double> ref(n), kept(n);
        rk4_step<double>(*dyn, xu.data(), xu.data() + n, nullptr, 0.1, substeps, ref.data(), steps);
        altro::KeptField field(*dyn, xu.data() + n, altro::field_reads(*dyn));
        altro::rk4_step_kept(field, n, xu.data(), 0.1, substeps, kept.data(), steps);
        EXPECT_EQ(ref, kept) << dyn->type() << " substeps " << substeps << " steps " << steps;
      }
  // The unicycle reads its heading (bit 2): a mask without it reuses fields it must not.
  std::vector<double> ref(3), wrong(3);
  const std::vector<double>& xu = cases.back().second;
  rk4_step<double>(uni, xu.data(), xu.data() + 3, nullptr, 0.1, 4, ref.data());
  altro::KeptField blind(uni, xu.data() + 3, 0u);
  altro::rk4_step_kept(blind, 3, xu.data(), 0.1, 4, wrong.data());
  EXPECT_NE(ref, wrong);
}
