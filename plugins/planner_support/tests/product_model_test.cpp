// The shared product model against its definitions, on two unicycles with pair and obstacle
// rows: a rollout is the step repeated from x0, the product Jacobians are central differences of
// the step, and the rows' sparse Jacobian is central differences of g. The nlopt, ipopt and ompl
// planners rely on all three.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "marsyn/core/planning/constraints.hpp"
#include "marsyn/planner_support/product_model.hpp"
#include "marsyn/sampled_map.hpp"
#include "test_problems.hpp"

using namespace marsyn;
using planner_support::ProductModel;

namespace {

std::vector<Eigen::VectorXd> some_inputs(const ProductModel& M) {
  std::vector<Eigen::VectorXd> U(M.T, Eigen::VectorXd(M.m));
  for (int k = 0; k < M.T; ++k)
    for (int j = 0; j < M.m; ++j) U[k][j] = 0.5 * std::sin(0.7 * k + 1.3 * j);
  return U;
}

}  // namespace

TEST(ProductModel, RolloutRepeatsTheStepFromX0) {
  const auto p = testproblems::unicycle_crossing(6, true);
  const auto pp = planning::assemble(p, p.horizon);
  const ProductModel M(pp);
  ASSERT_EQ(M.n, 6);
  ASSERT_EQ(M.m, 4);
  ASSERT_EQ(M.T, 6);
  ASSERT_EQ(M.agents.size(), 2u);
  const auto U = some_inputs(M);
  const auto X = M.rollout(U);
  ASSERT_EQ(static_cast<int>(X.size()), M.T + 1);
  EXPECT_EQ(X[0], pp.x0);
  Eigen::VectorXd next(M.n);
  for (int k = 0; k < M.T; ++k) {
    M.step(X[k].data(), U[k].data(), next.data());
    EXPECT_EQ(X[k + 1], next) << "k = " << k;
  }
}

TEST(ProductModel, JacobiansAreCentralDifferencesOfTheStep) {
  const auto p = testproblems::unicycle_crossing(6, true);
  const auto pp = planning::assemble(p, p.horizon);
  const ProductModel M(pp);
  Eigen::VectorXd x = pp.x0, u = some_inputs(M)[2];
  x[2] += 0.4;
  Eigen::MatrixXd A, B;
  M.jacobians(x.data(), u.data(), A, B);
  ASSERT_EQ(A.rows(), M.n);
  ASSERT_EQ(A.cols(), M.n);
  ASSERT_EQ(B.cols(), M.m);
  const double h = 1e-6;
  Eigen::VectorXd fp(M.n), fm(M.n);
  for (int i = 0; i < M.n; ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += h, xm[i] -= h;
    M.step(xp.data(), u.data(), fp.data());
    M.step(xm.data(), u.data(), fm.data());
    EXPECT_LT(((fp - fm) / (2 * h) - A.col(i)).cwiseAbs().maxCoeff(), 1e-6) << "state " << i;
  }
  for (int j = 0; j < M.m; ++j) {
    Eigen::VectorXd up = u, um = u;
    up[j] += h, um[j] -= h;
    M.step(x.data(), up.data(), fp.data());
    M.step(x.data(), um.data(), fm.data());
    EXPECT_LT(((fp - fm) / (2 * h) - B.col(j)).cwiseAbs().maxCoeff(), 1e-6) << "input " << j;
  }
  // The agents do not interact through the dynamics: the off-diagonal blocks are zero.
  EXPECT_EQ(A.block(0, 3, 3, 3).norm(), 0.0);
  EXPECT_EQ(B.block(3, 0, 3, 2).norm(), 0.0);
}

TEST(RowSet, SparseJacobianIsCentralDifferencesOfTheRows) {
  const auto p = testproblems::unicycle_crossing(6, true);
  const auto pp = planning::assemble(p, p.horizon);
  const ProductModel M(pp);
  const auto& rows = M.path;
  ASSERT_GT(rows.rows(), 0);
  std::vector<int> r, c;
  rows.pattern(r, c);
  ASSERT_EQ(static_cast<int>(r.size()), rows.nonzeros());
  ASSERT_EQ(static_cast<int>(c.size()), rows.nonzeros());
  const Eigen::VectorXd x = M.rollout(some_inputs(M))[3];
  std::vector<double> g(rows.rows()), jac(rows.nonzeros());
  rows.evaluate(x.data(), g.data(), jac.data());
  Eigen::MatrixXd J(rows.rows(), M.n);  // dense() fills a matrix of this size
  rows.dense(jac.data(), J);
  const double h = 1e-6;
  std::vector<double> gp(rows.rows()), gm(rows.rows());
  for (int i = 0; i < M.n; ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp[i] += h, xm[i] -= h;
    rows.evaluate(xp.data(), gp.data(), nullptr);
    rows.evaluate(xm.data(), gm.data(), nullptr);
    for (int k = 0; k < rows.rows(); ++k) EXPECT_NEAR((gp[k] - gm[k]) / (2 * h), J(k, i), 1e-5) << "row " << k << ", state " << i;
  }
  // worst() is the largest row, named.
  std::string name;
  double largest = -INFINITY;
  for (double v : g) largest = std::max(largest, v);
  EXPECT_EQ(rows.worst(x.data(), &name), largest);
  EXPECT_FALSE(name.empty());
}

// A state bound's row is named by its agent and state, never by its product index ("upper bound
// of x4" told a user nothing); the goal's rows say so.
TEST(RowSet, BoundsAreNamedByAgentAndState) {
  const auto p = testproblems::unicycle_crossing(6, false);
  const auto pp = planning::assemble(p, p.horizon);
  const ProductModel M(pp);
  const std::vector<std::string> states = p.agents[1].dynamics->state_names();
  // right's second state far above every bound: that row is the worst.
  Eigen::VectorXd x = pp.x0;
  x[M.agents[1].xo + 1] = 1e6;
  std::string name;
  M.path.worst(x.data(), &name);
  EXPECT_EQ(name, "upper bound of " + states[1] + " of right");
  M.terminal.worst(x.data(), &name);
  EXPECT_EQ(name, "upper bound of " + states[1] + " of right (goal)");
  x[M.agents[1].xo + 1] = -1e6;
  M.path.worst(x.data(), &name);
  EXPECT_EQ(name, "lower bound of " + states[1] + " of right");
}

// Between the samples (continuous guarantee): the interior points are the sampled map's own
// substep states, their Jacobians are central differences, and the rows there count in the
// violation.
TEST(ProductModel, InteriorPointsAreTheMapsSubstepStates) {
  auto p = testproblems::unicycle_crossing(6, true);
  p.guarantee = Guarantee::Continuous;
  planning::AssemblyOptions three;
  three.between_points = 3;  // with 4 substeps: every substep state
  const auto pp = planning::assemble(p, p.horizon, three);
  const ProductModel M(pp);
  ASSERT_EQ(M.points, 3);
  ASSERT_EQ(p.rk4_substeps, 4);
  ASSERT_GT(M.between.rows(), 0);
  const auto U = some_inputs(M);
  const auto X = M.rollout(U);
  Eigen::VectorXd z(M.n), sub(M.n);
  for (int j = 1; j <= M.points; ++j) {
    M.interior(X[2].data(), U[2].data(), j, z.data());
    for (const auto& a : M.agents)
      rk4_step<double>(*a.dyn, X[2].data() + a.xo, U[2].data() + a.uo, nullptr, M.tau, M.substeps, sub.data() + a.xo, j);
    EXPECT_LT((z - sub).cwiseAbs().maxCoeff(), 1e-14) << "j = " << j;
    std::vector<double> all(static_cast<size_t>(M.points) * 3);
    flow_points(*M.agents[0].dyn, X[2].data(), U[2].data(), M.tau, M.substeps, M.points, all.data());
    for (int c = 0; c < 3; ++c) EXPECT_EQ(all[(j - 1) * 3 + c], sub[c]) << "j = " << j << ", c = " << c;
  }
}

TEST(ProductModel, InteriorJacobiansAreCentralDifferences) {
  auto p = testproblems::unicycle_crossing(6, true);
  p.guarantee = Guarantee::Continuous;
  const auto pp = planning::assemble(p, p.horizon);
  const ProductModel M(pp);
  Eigen::VectorXd x = pp.x0, u = some_inputs(M)[3];
  x[2] += 0.7;
  x[5] -= 0.3;
  const double h = 1e-6;
  for (int j = 1; j <= M.points; ++j) {
    Eigen::MatrixXd A, B;
    M.interior_jacobians(x.data(), u.data(), j, A, B);
    Eigen::VectorXd fp(M.n), fm(M.n);
    for (int c = 0; c < M.n; ++c) {
      Eigen::VectorXd xp = x, xm = x;
      xp[c] += h;
      xm[c] -= h;
      M.interior(xp.data(), u.data(), j, fp.data());
      M.interior(xm.data(), u.data(), j, fm.data());
      EXPECT_LT((A.col(c) - (fp - fm) / (2 * h)).cwiseAbs().maxCoeff(), 1e-7) << "j = " << j << ", x" << c;
    }
    for (int c = 0; c < M.m; ++c) {
      Eigen::VectorXd up = u, um = u;
      up[c] += h;
      um[c] -= h;
      M.interior(x.data(), up.data(), j, fp.data());
      M.interior(x.data(), um.data(), j, fm.data());
      EXPECT_LT((B.col(c) - (fp - fm) / (2 * h)).cwiseAbs().maxCoeff(), 1e-7) << "j = " << j << ", u" << c;
    }
    EXPECT_GT(B.cwiseAbs().maxCoeff(), 1e-3);  // the input moves the point: not a vacuous check
  }
}

TEST(ProductModel, ViolationCountsTheRowsBetweenTheSamples) {
  // One unicycle whose samples straddle a thin wall: every knot clears it, the flow does not.
  auto p = testproblems::unicycle_obstacle(2);
  p.guarantee = Guarantee::Continuous;
  p.tau = 1.0;
  p.obstacles[0].vertices = {{2.95, -1}, {3.05, -1}, {3.05, 1}, {2.95, 1}};
  p.agents[0].x0 = Eigen::Vector3d(2.0, 0, 0);
  auto pp = planning::assemble(p, p.horizon);
  ProductModel M(pp);
  std::vector<Eigen::VectorXd> U(2, Eigen::Vector2d(2.0, 0.0));  // 2 m per period: over the wall
  const auto X = M.rollout(U);
  ASSERT_NEAR(X[1][0], 4.0, 1e-9);
  EXPECT_LE(M.path.worst(X[1].data(), nullptr), 0.0);  // the knot is clear of the wall
  std::string worst;
  EXPECT_GT(M.violation(X, U, &worst), 0.3);
  EXPECT_NE(worst.find("between k = 0 and 1"), std::string::npos) << worst;
  p.guarantee = Guarantee::Sampled;  // the paper's semantics: only the knots count
  pp = planning::assemble(p, p.horizon);
  const ProductModel S(pp);
  EXPECT_EQ(S.points, 0);
  EXPECT_LT(S.violation(X, U, nullptr), 0.3);
}
