// FCL distances against exact point-polygon distances computed here from the definition.
#include <gtest/gtest.h>

#include <random>

#include "fcl_distance.hpp"

using namespace marsyn;
using fcl_collision::FclDistance;

namespace {

// Exact signed distance: outside, the distance to the nearest edge segment; inside, minus the
// distance to the nearest edge line (for a convex polygon the same as to the nearest segment).
double exact(const std::vector<Eigen::Vector2d>& v, const Eigen::Vector2d& p) {
  const size_t k = v.size();
  double seg = 1e300;
  bool inside = true;
  for (size_t i = 0; i < k; ++i) {
    const Eigen::Vector2d a = v[i], b = v[(i + 1) % k], e = b - a;
    const double t = std::clamp((p - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
    seg = std::min(seg, (a + t * e - p).norm());
    if (e.x() * (p - a).y() - e.y() * (p - a).x() < 0) inside = false;
  }
  return inside ? -seg : seg;
}

Obstacle poly(std::vector<Eigen::Vector2d> v, bool box = false) {
  Obstacle o;
  o.vertices = std::move(v);
  o.is_box = box;
  return o;
}

const std::vector<Obstacle>& scene() {
  static const std::vector<Obstacle> s = {
      poly({{4, 4}, {6, 4}, {6, 6}, {4, 6}}, true),
      poly({{0, 0}, {3, 0.5}, {2.5, 2.5}, {0.5, 2}}),
      poly({{-2, -1}, {-1, -3}, {0, -1}}),
  };
  return s;
}

}  // namespace

TEST(FclDistance, MatchesExactDistancesOutsideAndInside) {
  FclDistance fcl(scene());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-4, 8);
  double worst_out = 0, worst_in = 0;
  int inside = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const Eigen::Vector2d p(U(rng), U(rng));
    for (int o = 0; o < 3; ++o) {
      double g[2];
      const double d = fcl.distance(o, p.data(), g);
      const double e = exact(scene()[o].vertices, p);
      (e > 0 ? worst_out : worst_in) = std::max(e > 0 ? worst_out : worst_in, std::abs(d - e));
      if (e < 0) ++inside;
      EXPECT_NEAR(std::hypot(g[0], g[1]), 1.0, 1e-9);
      // The gradient is the derivative of the exact distance (away from the medial axis).
      const double h = 1e-6;
      const Eigen::Vector2d px = p + Eigen::Vector2d(h, 0), py = p + Eigen::Vector2d(0, h);
      const Eigen::Vector2d num((exact(scene()[o].vertices, px) - e) / h, (exact(scene()[o].vertices, py) - e) / h);
      if (std::abs(num.norm() - 1.0) < 1e-4) {
        EXPECT_NEAR(g[0], num.x(), 1e-3) << "obstacle " << o << " at " << p.transpose();
        EXPECT_NEAR(g[1], num.y(), 1e-3) << "obstacle " << o << " at " << p.transpose();
      }
    }
  }
  EXPECT_GT(inside, 50);
  EXPECT_LT(worst_out, 1e-6);
  EXPECT_LT(worst_in, 1e-6);
  std::cout << "largest error outside " << worst_out << ", inside " << worst_in << " (" << inside << " inside)\n";
}

TEST(FclDistance, OverlapIsMinusThePenetrationDepth) {
  FclDistance fcl(scene());
  const double centre[2] = {5, 5}, near_left[2] = {4.1, 5.3};
  double g[2];
  EXPECT_NEAR(fcl.distance(0, centre, g), -1.0, 1e-9);
  EXPECT_NEAR(fcl.distance(0, near_left, g), -0.1, 1e-9);
  EXPECT_NEAR(g[0], -1.0, 1e-12);
  EXPECT_NEAR(g[1], 0.0, 1e-12);
  const double corner[2] = {7, 7};
  EXPECT_NEAR(fcl.distance(0, corner, g), std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(g[0], std::sqrt(0.5), 1e-9);
}

TEST(FclDistance, ParamsRoundTripAndRejectBadInput) {
  FclDistance fcl(FclDistance::params_for(scene()));
  EXPECT_EQ(fcl.obstacles(), 3);
  Params boxes;
  boxes.set("boxes", std::vector<double>{0, 0, 1, 1, 2, 2, 3, 3});
  FclDistance two(boxes);
  const double p[2] = {1.5, 0.5};
  EXPECT_NEAR(two.distance(0, p, nullptr), 0.5, 1e-9);
  Params bad;
  bad.set("boxes", std::vector<double>{0, 0, 1});
  EXPECT_THROW(FclDistance{bad}, ParamError);
  Params bad_poly;
  bad_poly.set("polygons", std::vector<double>{3, 0, 0, 1, 0});
  EXPECT_THROW(FclDistance{bad_poly}, ParamError);
}

TEST(FclDistance, ExactNearTheBoundary) {
  // Points within 1e-4 of an edge, on both sides: where a planner's constraint is active.
  FclDistance fcl(scene());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> t(0, 1), off(-1e-4, 1e-4);
  double worst = 0;
  for (int o = 0; o < 3; ++o) {
    const auto& v = scene()[o].vertices;
    for (int trial = 0; trial < 2000; ++trial) {
      const size_t i = trial % v.size();
      const Eigen::Vector2d a = v[i], b = v[(i + 1) % v.size()], e = (b - a).normalized();
      const Eigen::Vector2d p = a + t(rng) * (b - a) + off(rng) * Eigen::Vector2d(e.y(), -e.x());
      worst = std::max(worst, std::abs(fcl.distance(o, p.data(), nullptr) - exact(v, p)));
    }
  }
  EXPECT_LT(worst, 1e-7);
  std::cout << "largest error near edges " << worst << "\n";
}
