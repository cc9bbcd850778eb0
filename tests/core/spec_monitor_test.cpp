#include <gtest/gtest.h>

#include <random>

#include "marsyn/core/verification/spec_monitor.hpp"

namespace {
using V = Eigen::Vector2d;

// Brute force: distance from p to a dense sampling of the polygon's boundary (outside points).
double brute(const std::vector<V>& poly, const V& p, bool inf) {
  double best = 1e300;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const V a = poly[i], b = poly[(i + 1) % poly.size()];
    for (int s = 0; s <= 20000; ++s) {
      const V q = a + (b - a) * (s / 20000.0);
      best = std::min(best, inf ? (p - q).lpNorm<Eigen::Infinity>() : (p - q).norm());
    }
  }
  return best;
}
}  // namespace

TEST(SpecMonitor, InfNormDistanceToPolygonMatchesBruteForce) {
  const std::vector<V> tri{{-1, 2.4}, {8, 2.4}, {-1, 9.15}};  // counter-clockwise
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ux(-4, 11), uy(-1, 12);
  int outside = 0;
  for (int t = 0; t < 300; ++t) {
    const V p(ux(rng), uy(rng));
    const double d_inf = marsyn::signed_distance_inf(tri, p);
    const double d_two = marsyn::signed_distance_two(tri, p);
    if (d_inf > 0) {
      ++outside;
      EXPECT_NEAR(d_inf, brute(tri, p, true), 1e-3) << p.transpose();
      EXPECT_NEAR(d_two, brute(tri, p, false), 1e-3) << p.transpose();
    } else {
      EXPECT_LE(d_two, 0.0);
    }
  }
  EXPECT_GT(outside, 100);
}

TEST(SpecMonitor, InsideDepthOfABoxIsTheDistanceToTheNearestSide) {
  const std::vector<V> box{{4, 4}, {6, 4}, {6, 6}, {4, 6}};
  EXPECT_NEAR(marsyn::signed_distance_inf(box, V(5, 5)), -1.0, 1e-12);
  EXPECT_NEAR(marsyn::signed_distance_inf(box, V(4.2, 5.5)), -0.2, 1e-12);
  EXPECT_NEAR(marsyn::signed_distance_inf(box, V(7, 7.5)), 1.5, 1e-12);  // corner: max(1, 1.5)
  EXPECT_NEAR(marsyn::signed_distance_two(box, V(7, 7.5)), std::sqrt(1 + 2.25), 1e-12);
}

TEST(SpecMonitor, InsideDepthOfATiltedEdgeUsesTheInfNorm) {
  // The hypotenuse x + y = 2 of the triangle (0,0), (2,0), (0,2): from (0.5, 0.5) the Euclidean
  // distance is 1/sqrt(2); an inf-norm box reaches the line at r = 0.5, but the legs are closer.
  const std::vector<V> tri{{0, 0}, {2, 0}, {0, 2}};
  EXPECT_NEAR(marsyn::signed_distance_inf(tri, V(0.9, 0.9)), -0.1, 1e-12);  // (2 - 1.8) / |n|_1 * |n|_2 ... = 0.1
  EXPECT_NEAR(marsyn::signed_distance_two(tri, V(0.9, 0.9)), -0.2 / std::sqrt(2.0), 1e-12);
}
