// Routes around obstacles: the shortest path around convex polygons through their corners, and
// the waypoints a problem gets where its agents' straight lines are blocked.
#include <gtest/gtest.h>

#include <cmath>

#include "marsyn/core/planning/routes.hpp"

using namespace marsyn;
using namespace marsyn::planning;

namespace {

Polygon box(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

double length(const Eigen::Vector2d& a, const std::vector<Eigen::Vector2d>& corners, const Eigen::Vector2d& b) {
  double L = 0;
  Eigen::Vector2d p = a;
  for (const auto& c : corners) L += (c - p).norm(), p = c;
  return L + (b - p).norm();
}

}  // namespace

TEST(Routes, AFreeSegmentNeedsNoCorner) {
  bool found = false;
  EXPECT_TRUE(shortest_route({box(1, 1, 2, 2)}, {0, 0}, {3, 0}, &found).empty());
  EXPECT_TRUE(found);
  // Along an edge is not through the interior.
  EXPECT_TRUE(shortest_route({box(1, 0, 2, 2)}, {0, 0}, {3, 0}, &found).empty());
  EXPECT_TRUE(found);
}

TEST(Routes, AroundABoxThroughTheNearerCorners) {
  bool found = false;
  const auto r = shortest_route({box(1, -1, 2, 2)}, {0, 0}, {3, 0}, &found);
  ASSERT_TRUE(found);
  ASSERT_EQ(r.size(), 2u);  // under the box: (1, -1), (2, -1)
  EXPECT_EQ(r[0], Eigen::Vector2d(1, -1));
  EXPECT_EQ(r[1], Eigen::Vector2d(2, -1));
  EXPECT_NEAR(length({0, 0}, r, {3, 0}), 2 * std::sqrt(2.0) + 1, 1e-12);
}

TEST(Routes, AClosedGapIsGoneAround) {
  // Two boxes overlapping in the middle (a gap closed by their growth): the route passes
  // outside both, never between them.
  const std::vector<Polygon> grown{box(1, -0.05, 2, 3), box(1, -3, 2, 0.05)};
  bool found = false;
  const auto r = shortest_route(grown, {0, 0.5}, {3, 0.5}, &found);
  ASSERT_TRUE(found);
  ASSERT_FALSE(r.empty());
  for (const auto& c : r) EXPECT_GE(std::abs(c.y()), 3.0 - 1e-12);
}

TEST(Routes, NoRouteFromInsideOrOutOfAClosedRing) {
  bool found = true;
  EXPECT_TRUE(shortest_route({box(-1, -1, 1, 1)}, {0, 0}, {3, 0}, &found).empty());
  EXPECT_FALSE(found);
}

TEST(Routes, WaypointsOnlyForBlockedAgents) {
  Problem p;
  p.delta = 0.2;
  p.delta_norm = Norm::Inf;
  auto agent = [](double y) {
    AgentSpec a;
    a.name = "a" + std::to_string(static_cast<int>(y));
    a.x0 = Eigen::Vector2d(0, y);
    a.goal = {Eigen::Vector2d(9.5, y - 0.5), Eigen::Vector2d(10.5, y + 0.5)};
    a.state_bounds = {Eigen::Vector2d(-1, -20), Eigen::Vector2d(11, 20)};
    a.input_bounds = {Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1)};
    a.tube.eps = Eigen::Vector2d(0.1, 0.1);
    a.tube.w = Eigen::Vector2d(0, 0);
    return a;
  };
  p.agents = {agent(0), agent(10)};
  Obstacle o;
  o.name = "wall";
  o.vertices = box(4, -2, 6, 2);
  o.is_box = true;
  p.obstacles = {o};
  const auto w = route_waypoints(p, 100);
  ASSERT_EQ(w.size(), 2u);  // two corners for the first agent, none for the second
  for (const auto& wp : w) {
    EXPECT_TRUE(std::isfinite(wp.x[0]) && std::isfinite(wp.x[1]));
    EXPECT_TRUE(std::isnan(wp.x[2]) && std::isnan(wp.x[3]));
    EXPECT_GT(wp.step, 0);
    EXPECT_LT(wp.step, 100);
  }
  EXPECT_LT(w[0].step, w[1].step);
  // Grown by 1.1 (delta + eps) = 0.33: the corners sit outside the grown wall.
  EXPECT_NEAR(std::abs(w[0].x[1]), 2.33, 1e-9);
}
