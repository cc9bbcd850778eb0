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

namespace {
Box box3(double x0, double y0, double z0, double x1, double y1, double z1) {
  Box b{Eigen::VectorXd(3), Eigen::VectorXd(3)};
  b.lo << x0, y0, z0;
  b.hi << x1, y1, z1;
  return b;
}
}  // namespace

// The certifier's 3-D margins: a pair that clears in x-y only when the heights are ignored, and
// prisms bounded in z, against sampled points of both (a lower bound, tight).
TEST(BoxMargins, ThreeDPairsAndPrisms) {
  // Two boxes over the same x-y square, 0.2 apart in height: a collision with delta 0.25 (the
  // plane's box margin would say they overlap; in space they are 0.2 apart).
  const Box a = box3(0, 0, 0, 1, 1, 1), b = box3(0, 0, 1.2, 1, 1, 2);
  for (Norm norm : {Norm::Inf, Norm::Two}) {
    EXPECT_NEAR(box_pair_margin(a, b, 0.25, norm), 0.2 - 0.25, 1e-15);
    EXPECT_NEAR(box_pair_margin(a, b, 0.1, norm), 0.2 - 0.1, 1e-15);
  }
  // Apart in x by 1 and in z by 1: inf-norm 1, 2-norm sqrt(2).
  const Box c = box3(2, 0, 2, 3, 1, 3);
  EXPECT_DOUBLE_EQ(box_pair_margin(a, c, 0.0, Norm::Inf), 1.0);
  EXPECT_NEAR(box_pair_margin(a, c, 0.0, Norm::Two), std::sqrt(2.0), 1e-15);
  // Formation in space: distances between a and c range over [sqrt(2), |(3, 1, 3)|].
  EXPECT_NEAR(box_formation_margin(a, c, 3.0, 2.0), std::min(std::sqrt(2.0) - 1.0, 5.0 - std::sqrt(19.0)), 1e-12);
  // A slab at heights [1, 2] over [0, 4]^2; a box under it, and one beyond an edge and below.
  Obstacle slab;
  slab.vertices = square(0, 0, 4, 4);
  slab.z_lo = 1;
  slab.z_hi = 2;
  EXPECT_NEAR(box_obstacle_margin(box3(1, 1, 0, 2, 2, 0.5), slab, 0.0, Norm::Two), 0.5, 1e-15);
  EXPECT_NEAR(box_obstacle_margin(box3(1, 1, 0, 2, 2, 0.5), slab, 0.6, Norm::Inf), -0.1, 1e-15);
  EXPECT_NEAR(box_obstacle_margin(box3(5, 1, -1, 6, 2, 0), slab, 0.0, Norm::Two), std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(box_obstacle_margin(box3(5, 1, -1, 6, 2, 0), slab, 0.0, Norm::Inf), 1.0, 1e-15);
  EXPECT_LT(box_obstacle_margin(box3(1, 1, 0.5, 2, 2, 1.5), slab, 0.0, Norm::Two), 0.0);
  // A planar box (2 coordinates) in a 3-D problem is judged by x-y alone: never above.
  EXPECT_LT(box_obstacle_margin(box2(1, 1, 2, 2), slab, 0.0, Norm::Two), 0.0);
  // Random prisms and boxes: a lower bound of the sampled distance.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-3, 3), r(0.05, 1.0);
  int tight = 0, cases = 0;
  for (int t = 0; t < 200; ++t) {
    Obstacle o;
    const double x0 = u(rng), y0 = u(rng);
    o.vertices = square(x0, y0, x0 + r(rng) * 2, y0 + r(rng) * 2);
    o.z_lo = u(rng);
    o.z_hi = o.z_lo + r(rng) * 2;
    const double x = u(rng), y = u(rng), z = u(rng);
    const Box B = box3(x, y, z, x + r(rng), y + r(rng), z + r(rng));
    for (Norm norm : {Norm::Inf, Norm::Two}) {
      // Separable: the x-y distance of the box and the polygon, and the gap of the heights.
      const double dxy = sampled_distance(box2(B.lo[0], B.lo[1], B.hi[0], B.hi[1]), o.vertices, norm, 60);
      const bool overlap_xy = box_obstacle_margin(box2(B.lo[0], B.lo[1], B.hi[0], B.hi[1]), o.vertices, 0.0, norm) < 0;
      const double dz = std::max({0.0, o.z_lo - B.hi[2], B.lo[2] - o.z_hi});
      const double exact = norm == Norm::Inf ? std::max(overlap_xy ? 0.0 : dxy, dz)
                                             : std::hypot(overlap_xy ? 0.0 : dxy, dz);
      const double m = box_obstacle_margin(B, o, 0.0, norm);
      if (exact < 1e-9) continue;
      ++cases;
      EXPECT_LE(m, exact + 1e-12) << "not a lower bound, trial " << t;
      if (m >= exact - 0.05 * (1 + exact)) ++tight;
    }
  }
  EXPECT_GT(tight, cases * 9 / 10);
}

// A `box` obstacle takes the box-to-box distance instead of the polygon's separating directions:
// the same lower bound (to rounding) as the polygon path on the same corners, in the plane and in
// space, separated or overlapping (the sign must agree).
TEST(BoxMargins, BoxObstaclesTakeTheBoxDistanceWithTheSameResult) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-3, 3), r(0.05, 1.5);
  int separated = 0;
  for (int t = 0; t < 400; ++t) {
    const double x = u(rng), y = u(rng), z = u(rng);
    Obstacle box;
    box.vertices = square(x, y, x + r(rng), y + r(rng));
    box.is_box = true;
    if (t % 2) box.z_lo = z, box.z_hi = z + r(rng);
    Obstacle poly = box;
    poly.is_box = false;
    const double wx = u(rng), wy = u(rng), wz = u(rng);
    const Box w = t % 4 < 2 ? box3(wx, wy, wz, wx + r(rng), wy + r(rng), wz + r(rng)) : box2(wx, wy, wx + r(rng), wy + r(rng));
    for (Norm norm : {Norm::Inf, Norm::Two}) {
      const double fast = box_obstacle_margin(w, box, 0.1, norm), slow = box_obstacle_margin(w, poly, 0.1, norm);
      ASSERT_EQ(fast + 0.1 > 0, slow + 0.1 > 0) << "trial " << t;
      if (slow + 0.1 > 0) {
        EXPECT_NEAR(fast, slow, 1e-12 * (1 + std::abs(slow))) << "trial " << t;
        ++separated;
      }
    }
  }
  EXPECT_GT(separated, 300);
}
