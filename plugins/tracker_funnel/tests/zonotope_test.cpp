#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "period_flow.hpp"
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


// The enclosure's generator product (dot_enclosure, docs/soundness.md section 2): the interval
// holds the exact dot product, computed here in quad precision (each product exact, the sum's
// own error far below the bound), on random terms spanning 2^-600..2^600 with cancellation, on
// terms that underflow, and on near-cancelling pairs. Without its error term (the plain
// round-to-nearest sum) the same draws leave the exact value out.
TEST(DotEnclosure, HoldsTheExactDotProduct) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mant(-1, 1);
  std::uniform_int_distribution<int> expo(-600, 600), len(1, 40), kind(0, 2);
  long missed_without = 0, draws = 0;
  for (int draw = 0; draw < 20000; ++draw) {
    const int N = len(rng), k = kind(rng);
    std::vector<double> a(N), b(N);
    for (int i = 0; i < N; ++i) {
      const int e = k == 0 ? expo(rng) / 2 : k == 1 ? -537 - expo(rng) % 2 : 0;  // 1: products near 2^-1074
      a[i] = std::ldexp(mant(rng), e);
      b[i] = std::ldexp(mant(rng), k == 0 ? expo(rng) / 2 : e);
    }
    if (k == 2 && N >= 2) {  // a pair that cancels to the last bits
      a[1] = -a[0] * (1 + std::ldexp(1.0, -50));
      b[1] = b[0];
    }
    __float128 exact = 0, magnitude = 0;
    for (int i = 0; i < N; ++i) {
      const __float128 p = static_cast<__float128>(a[i]) * static_cast<__float128>(b[i]);
      exact += p;
      magnitude += p < 0 ? -p : p;
    }
    const __float128 slack = magnitude * static_cast<__float128>(std::ldexp(1.0, -100));  // the quad sum's own error
    const FastInterval r = dot_enclosure(a.data(), b.data(), 1, N);
    ++draws;
    ASSERT_LE(static_cast<__float128>(r.lower()), exact - slack) << "draw " << draw << ", N " << N;
    ASSERT_GE(static_cast<__float128>(r.upper()), exact + slack) << "draw " << draw << ", N " << N;
    double s = 0;
    for (int i = 0; i < N; ++i) s += a[i] * b[i];
    if (static_cast<__float128>(s) != exact) ++missed_without;
  }
  std::printf("dot_enclosure: %ld draws held; the plain sum missed the exact value in %ld\n", draws, missed_without);
  EXPECT_GT(missed_without, draws / 10);  // the error term is what holds them
  // Strided (a row of J times a column of G stored with a stride) as contiguous.
  const double a[3] = {1.5, -2.25, 0.1}, b[6] = {2, 99, 4, 99, -3, 99};
  const FastInterval r = dot_enclosure(a, b, 2, 3);
  EXPECT_LE(r.lower(), 1.5 * 2 - 2.25 * 4 - 0.3);
  EXPECT_GE(r.upper(), 1.5 * 2 - 2.25 * 4 - 0.3);
  // Overflow: the whole line, never a finite wrong interval.
  const double big[2] = {1e300, 1e300};
  EXPECT_FALSE(std::isfinite(dot_enclosure(big, big, 1, 2).upper()));
}

}  // namespace
}  // namespace marsyn::funnel
