#include <gtest/gtest.h>

#include <random>

#include <Eigen/Dense>

#include "src/inequality_step.hpp"

using namespace marsyn::altro::detail;

namespace {
Eigen::SparseMatrix<double> lower_gram(const Eigen::MatrixXd& J) {
  const Eigen::MatrixXd G = J * J.transpose();
  return Eigen::MatrixXd(G.triangularView<Eigen::Lower>()).sparseView();
}

// The smallest |J' y| over every set of rows taken as equations at their bound whose step keeps
// all rows at or below it: the least-norm step of the inequalities, by enumeration.
double best_norm(const Eigen::MatrixXd& J, const Eigen::VectorXd& c) {
  const int R = static_cast<int>(c.size());
  double best = std::numeric_limits<double>::infinity();
  for (int mask = 1; mask < (1 << R); ++mask) {
    std::vector<int> set;
    for (int r = 0; r < R; ++r)
      if (mask >> r & 1) set.push_back(r);
    const Eigen::MatrixXd JS = J(set, Eigen::all);
    const Eigen::VectorXd yS = (JS * JS.transpose()).ldlt().solve(-c(set));
    const Eigen::VectorXd dU = JS.transpose() * yS;
    if (((c + J * dU).array() <= 1e-9).all()) best = std::min(best, dU.norm());
  }
  return best;
}
}  // namespace

// A satisfied row beside a nearly parallel violated one: held at its value it would demand a
// step a hundred times the violation; as an inequality it is carried along.
TEST(InequalityStep, ANearlyParallelSatisfiedRowDoesNotBlowTheStepUp) {
  Eigen::MatrixXd J(2, 2);
  J << 1.0, 0.0, 1.0, 0.01;
  const Eigen::VectorXd c = Eigen::Vector2d(0.02, -0.0005);
  Eigen::VectorXd y;
  ASSERT_TRUE(inequality_step(lower_gram(J), c, 1e-12, 20, y));
  const Eigen::VectorXd dU = J.transpose() * y;
  EXPECT_NEAR(dU[0], -0.02, 1e-9);
  EXPECT_NEAR(dU[1], 0.0, 1e-9);
  EXPECT_LE((c + J * dU).maxCoeff(), 1e-12);
  // Held as an equation, the second row gives |dU| of about 2.
  const Eigen::VectorXd held = J.fullPivLu().solve(Eigen::Vector2d(-0.02, 0.0));
  EXPECT_GT(held.norm(), 1.0);
}

// A satisfied row the violated row's step would break joins and ends at its bound.
TEST(InequalityStep, ARowTheStepWouldBreakJoinsAtItsBound) {
  Eigen::MatrixXd J(2, 2);
  J << 1.0, 0.0, -1.0, 1.0;
  const Eigen::VectorXd c = Eigen::Vector2d(0.02, -0.005);
  Eigen::VectorXd y;
  ASSERT_TRUE(inequality_step(lower_gram(J), c, 1e-12, 20, y));
  const Eigen::VectorXd dU = J.transpose() * y;
  EXPECT_NEAR(dU[0], -0.02, 1e-9);
  EXPECT_NEAR(dU[1], -0.015, 1e-9);
  EXPECT_NEAR((c + J * dU)[1], 0.0, 1e-12);
}

TEST(InequalityStep, NothingViolatedIsNoStep) {
  Eigen::MatrixXd J = Eigen::MatrixXd::Identity(2, 3);
  Eigen::VectorXd y;
  EXPECT_FALSE(inequality_step(lower_gram(J), Eigen::Vector2d(-0.1, 0.0), 1e-12, 20, y));
}

// Random rows (fewer than the inputs): the step keeps every row at or below its bound to first
// order, with the multipliers' sign, and is the least-norm such step (found by enumeration).
TEST(InequalityStep, RandomRowsGiveTheLeastNormFeasibleStep) {
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> val(-1.0, 1.0);
  int optimal = 0;
  const int cases = 300;
  for (int t = 0; t < cases; ++t) {
    const int R = 2 + static_cast<int>(gen() % 5), n = R + 1 + static_cast<int>(gen() % 4);
    Eigen::MatrixXd J(R, n);
    for (int r = 0; r < R; ++r)
      for (int k = 0; k < n; ++k) J(r, k) = val(gen);
    if (t % 2) J.row(1) = J.row(0) + 0.01 * J.row(1);  // nearly parallel pairs, as at interior points
    Eigen::VectorXd c(R);
    for (int r = 0; r < R; ++r) c[r] = 0.02 * val(gen);
    if ((c.array() <= 0).all()) c[0] = 0.01;
    Eigen::VectorXd y;
    ASSERT_TRUE(inequality_step(lower_gram(J), c, 1e-14, 50, y)) << t;
    const Eigen::VectorXd dU = J.transpose() * y;
    EXPECT_LE((c + J * dU).maxCoeff(), 1e-9) << t;
    EXPECT_LE(y.maxCoeff(), 0.0) << t;
    const double best = best_norm(J, c);
    EXPECT_LE(best, dU.norm() + 1e-9) << t;  // enumeration finds the step itself at least
    optimal += dU.norm() <= best * (1 + 1e-6) + 1e-12;
  }
  EXPECT_EQ(optimal, cases);
}
