// The spec on boxes (box_margins.hpp): exact values on hand-computed cases, and against brute
// force on random boxes and polygons a lower bound of the true margin that is also tight.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "marsyn/core/planning/box_margins.hpp"

using namespace marsyn;
using namespace marsyn::planning;

namespace {

Box box2(double x0, double y0, double x1, double y1) {
  Box b{Eigen::VectorXd(2), Eigen::VectorXd(2)};
  b.lo << x0, y0;
  b.hi << x1, y1;
  return b;
}

Polygon square(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

// Smallest distance between points of the box and the polygon, by dense sampling of both
// boundaries (an upper bound of the true distance, converging to it).
double sampled_distance(const Box& b, const Polygon& P, Norm norm, int per_edge = 200) {
  std::vector<Eigen::Vector2d> pa, pp;
  const Polygon A = {{b.lo[0], b.lo[1]}, {b.hi[0], b.lo[1]}, {b.hi[0], b.hi[1]}, {b.lo[0], b.hi[1]}};
  for (const Polygon* Q : {&A, &P})
    for (size_t e = 0; e < Q->size(); ++e)
      for (int t = 0; t <= per_edge; ++t) {
        const double s = static_cast<double>(t) / per_edge;
        (Q == &A ? pa : pp).push_back((1 - s) * (*Q)[e] + s * (*Q)[(e + 1) % Q->size()]);
      }
  double best = 1e300;
  for (const auto& a : pa)
    for (const auto& p : pp) best = std::min(best, norm == Norm::Inf ? (a - p).lpNorm<Eigen::Infinity>() : (a - p).norm());
  return best;
}

}  // namespace

TEST(BoxMargins, ObstacleExactCases) {
  const Polygon P = square(2, 0, 3, 1);
  EXPECT_DOUBLE_EQ(box_obstacle_margin(box2(0, 0, 1, 1), P, 0.0, Norm::Inf), 1.0);
  EXPECT_DOUBLE_EQ(box_obstacle_margin(box2(0, 0, 1, 1), P, 0.25, Norm::Two), 0.75);
  const Polygon Q = square(2, 2, 3, 3);  // diagonal: corner to corner
  EXPECT_NEAR(box_obstacle_margin(box2(0, 0, 1, 1), Q, 0.0, Norm::Inf), 1.0, 1e-15);
  EXPECT_NEAR(box_obstacle_margin(box2(0, 0, 1, 1), Q, 0.0, Norm::Two), std::sqrt(2.0), 1e-15);
  // A diamond: the inf-distance from the box to the slanted edge x + y = 4 is (4 - 2) / 2.
  const Polygon D = {{3, 1}, {4, 2}, {3, 3}, {2, 2}};
  EXPECT_NEAR(box_obstacle_margin(box2(0, 0, 1, 1), D, 0.0, Norm::Inf), 1.0, 1e-15);
  EXPECT_NEAR(box_obstacle_margin(box2(0, 0, 1, 1), D, 0.0, Norm::Two), std::sqrt(2.0), 1e-15);
  // Overlap is negative.
  EXPECT_LT(box_obstacle_margin(box2(0, 0, 2.5, 1), P, 0.0, Norm::Inf), 0.0);
}

TEST(BoxMargins, ObstacleIsASoundAndTightLowerBound) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-3, 3), r(0.05, 1.0);
  int tight = 0;
  for (int t = 0; t < 300; ++t) {
    // A random convex polygon: hull of random points around a centre.
    std::vector<Eigen::Vector2d> pts;
    const Eigen::Vector2d c(u(rng), u(rng));
    for (int k = 0; k < 7; ++k) pts.push_back(c + Eigen::Vector2d(r(rng) * std::cos(k), r(rng) * std::sin(k)) * 1.5);
    const Polygon P = convex_hull(pts);
    const double x = u(rng), y = u(rng);
    const Box B = box2(x, y, x + r(rng), y + r(rng));
    for (Norm norm : {Norm::Inf, Norm::Two}) {
      const double exact = sampled_distance(B, P, norm);
      const double m = box_obstacle_margin(B, P, 0.0, norm);
      if (exact < 1e-9) continue;  // touching or overlapping: only the sign matters
      EXPECT_LE(m, exact + 1e-12) << "not a lower bound, trial " << t;
      if (m >= exact - 0.02 * (1 + exact)) ++tight;
    }
  }
  EXPECT_GT(tight, 300);  // tight on almost every separated case (the sampling error is 1/200 edge)
}

TEST(BoxMargins, PairAndFormation) {
  const Box a = box2(0, 0, 1, 1), b = box2(3, 0.5, 4, 2), c = box2(2, 3, 3, 4);
  EXPECT_DOUBLE_EQ(box_pair_margin(a, b, 0.5, Norm::Inf), 1.5);
  EXPECT_DOUBLE_EQ(box_pair_margin(a, b, 0.5, Norm::Two), 1.5);
  EXPECT_DOUBLE_EQ(box_pair_margin(a, c, 0.0, Norm::Inf), 2.0);
  EXPECT_NEAR(box_pair_margin(a, c, 0.0, Norm::Two), std::sqrt(5.0), 1e-15);
  EXPECT_LT(box_pair_margin(a, box2(0.5, 0.5, 2, 2), 0.0, Norm::Inf), 0.0);
  // Formation: distances between the boxes range over [2, |(4, 2)|] for a and b.
  const double far = std::sqrt(16.0 + 4.0);
  EXPECT_NEAR(box_formation_margin(a, b, 3.0, 1.0), 4.0 - far, 1e-12);  // the far corners exceed 4
  EXPECT_NEAR(box_formation_margin(a, b, 3.5, 1.5), 0.0, 1e-12);         // the near sides exactly at 2
  EXPECT_NEAR(box_formation_margin(a, b, 3.0, 2.0), std::min(1.0, 5.0 - far), 1e-12);
  EXPECT_LT(box_formation_margin(a, b, 3.0, 0.5), 0.0);
}

TEST(BoxMargins, InsideBounds) {
  EXPECT_DOUBLE_EQ(box_inside_margin(box2(0.5, 0.5, 1, 1), box2(0, 0, 2, 2)), 0.5);
  EXPECT_LT(box_inside_margin(box2(-0.1, 0.5, 1, 1), box2(0, 0, 2, 2)), 0.0);
}
