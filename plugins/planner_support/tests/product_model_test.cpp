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
