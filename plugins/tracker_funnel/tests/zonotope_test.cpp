#include <gtest/gtest.h>

#include <random>

#include "zonotope.hpp"

namespace marsyn::funnel {
namespace {

TEST(Zonotope, FromIntervalsContainsEveryRealisation) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(-1, 1), U01(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + trial % 5, p = trial % 7;
    IVector c(n);
    IMatrix G(n, p);
    for (int i = 0; i < n; ++i) {
      const double a = U(rng), b = a + 0.1 * U01(rng);
      c[i] = FastInterval(a, b);
      for (int j = 0; j < p; ++j) {
        const double g = U(rng), h = g + 0.01 * U01(rng);
        G(i, j) = FastInterval(g, h);
      }
    }
    const Zonotope z = from_intervals(c, G, {});
    for (int s = 0; s < 200; ++s) {
      // A point with every interval realised at a random value: it must lie in the hull.
      std::vector<double> xi(p);
      for (auto& v : xi) v = U(rng);
      for (int i = 0; i < n; ++i) {
        double x = c[i].lower() + U01(rng) * (c[i].upper() - c[i].lower());
        for (int j = 0; j < p; ++j) x += (G(i, j).lower() + U01(rng) * (G(i, j).upper() - G(i, j).lower())) * xi[j];
        const FastInterval h = z.hull(i);
        EXPECT_LE(h.lower(), x);
        EXPECT_GE(h.upper(), x);
      }
    }
  }
}

TEST(Zonotope, ReductionKeepsTheBasisAndGrowsTheHull) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(-1, 1);
  Zonotope z;
  z.c = Eigen::VectorXd::Zero(4);
  z.G = Eigen::MatrixXd::NullaryExpr(4, 30, [&] { return U(rng); });
  const Eigen::MatrixXd basis = z.G.leftCols(4);
  Zonotope r = z;
  reduce_order(r, 4, 12);
  EXPECT_LE(r.generators(), 12);
  EXPECT_TRUE(r.G.leftCols(4) == basis);
  for (int i = 0; i < 4; ++i) EXPECT_GE(r.radius(i), z.radius(i) * (1 - 1e-15));
  // The removed generators' box is exactly their absolute row sums: the total radius is kept.
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(r.radius(i), z.radius(i), 1e-12);
}

TEST(Zonotope, ReductionContainsRandomPoints) {
  // Every point c + G xi is c + (kept) xi_k + (removed) xi_r, and the removed part lies in the
  // box: check the box really bounds it, point by point.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> U(-1, 1);
  Zonotope z;
  z.c = Eigen::VectorXd::Zero(3);
  z.G = Eigen::MatrixXd::NullaryExpr(3, 20, [&] { return U(rng); });
  Zonotope r = z;
  reduce_order(r, 3, 9);
  // Columns of r after the 3 basis columns that equal a column of z are kept ones; the last 3
  // columns are the box.
  const Eigen::MatrixXd box = r.G.rightCols(3);
  for (int s = 0; s < 1000; ++s) {
    Eigen::VectorXd xi = Eigen::VectorXd::NullaryExpr(20, [&] { return U(rng); });
    Eigen::VectorXd removed = Eigen::VectorXd::Zero(3);
    for (int j = 3; j < 20; ++j) {
      bool kept = false;
      for (int l = 3; l < r.generators() - 3; ++l) kept |= r.G.col(l) == z.G.col(j);
      if (!kept) removed += z.G.col(j) * xi[j];
    }
    for (int i = 0; i < 3; ++i) EXPECT_LE(std::fabs(removed[i]), box(i, i) * (1 + 1e-15));
  }
}

}  // namespace
}  // namespace marsyn::funnel
