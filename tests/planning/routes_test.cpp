// Routes around obstacles: the shortest path around convex polygons through their corners, and
// the waypoints a problem gets where its agents' straight lines are blocked.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "marsyn/core/planning/routes.hpp"

using namespace marsyn;
using namespace marsyn::planning;

namespace {

Polygon box(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

// A point agent of the plane (state = position), eps 0.1, starting at `from`, its goal the unit
// box around `goal`, inside `lo`..`hi`; in a problem of delta 0.2 (inf-norm) of its own.
Problem one_walker(const std::string& name, Eigen::Vector2d from, Eigen::Vector2d goal, Eigen::Vector2d lo,
                   Eigen::Vector2d hi) {
  Problem p;
  p.delta = 0.2;
  p.delta_norm = Norm::Inf;
  AgentSpec a;
  a.name = name;
  a.x0 = from;
  a.goal = {goal - Eigen::Vector2d(0.5, 0.5), goal + Eigen::Vector2d(0.5, 0.5)};
  a.state_bounds = {lo, hi};
  a.input_bounds = {Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1)};
  a.tube.eps = Eigen::Vector2d(0.1, 0.1);
  a.tube.w = Eigen::Vector2d(0, 0);
  p.agents = {a};
  return p;
}

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

// A round trip (start = goal) to a stage behind a wall: the straight way start-goal is no way at
// all, yet each leg (to the stage's region, back after its dwell) crosses the wall; each gets its
// corners, at knots inside the leg, outside the grown wall (issue 49, item 1).
TEST(RoutesForMissions, EachLegThroughTheStagesIsRouted) {
  Problem p = one_walker("fetch", {0, 0}, {0, 0}, {-5, -5}, {15, 15});
  AgentSpec& a = p.agents[0];
  MissionStage st;
  st.name = "shelf";
  st.polygon = {{9.5, -0.5}, {10.5, -0.5}, {10.5, 0.5}, {9.5, 0.5}};
  st.dwell = 10;
  a.stages = {st};
  Obstacle o;
  o.name = "wall";
  o.vertices = box(4, -2, 6, 2);
  o.is_box = true;
  p.obstacles = {o};
  MissionSchedule visits;
  visits.visit = {{40}};
  visits.horizon = 100;
  const auto w = route_waypoints(p, 100, visits);
  ASSERT_EQ(w.size(), 4u) << "two corners on the way there, two on the way back";
  for (int j = 0; j < 2; ++j) {
    EXPECT_GT(w[j].step, 0);
    EXPECT_LT(w[j].step, 40);
    EXPECT_GT(w[j + 2].step, 50);  // after the dwell
    EXPECT_LT(w[j + 2].step, 100);
  }
  for (const auto& wp : w) EXPECT_NEAR(std::abs(wp.x[1]), 2.33, 1e-9);  // outside the wall grown by 1.1 (delta + eps)
  // Without the stage the agent stays where it is: no way, no corner.
  p.agents[0].stages.clear();
  EXPECT_TRUE(route_waypoints(p, 100).empty());
  // A staged wall that binds only on the way back: corners on that leg only.
  p.agents[0].stages = {st};
  p.obstacles[0].staged = true;
  p.agents[0].stages[0].avoid_after = {0};
  const auto back = route_waypoints(p, 100, visits);
  ASSERT_EQ(back.size(), 2u);
  for (const auto& wp : back) EXPECT_GT(wp.step, 50);
}

// A stage that fixes the height only (a 3-D box region open in x and y) keeps the way's x and
// y: its point is the previous point's x, y at the region's height.
TEST(RoutesForMissions, AStageFixingOneCoordinateKeepsTheOthers) {
  Problem p;
  p.delta = 0.2;
  p.delta_norm = Norm::Inf;
  AgentSpec a;
  a.name = "lift";
  a.x0 = Eigen::Vector3d(0, 0, 0.5);
  a.goal = {Eigen::Vector3d(9.5, -0.5, 0.2), Eigen::Vector3d(10.5, 0.5, 0.8)};
  a.state_bounds = {Eigen::Vector3d(-1, -3, 0), Eigen::Vector3d(11, 3, 4)};
  a.input_bounds = {Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1)};
  a.tube.eps = Eigen::Vector3d(0.05, 0.05, 0.05);
  a.tube.w = Eigen::Vector3d::Zero();
  a.workspace.index = {0, 1, 2};
  a.workspace.offset = {0, 0, 0};
  MissionStage up;
  up.name = "up";
  up.box = {Eigen::Vector3d(-1, -3, 3), Eigen::Vector3d(11, 3, 3.6)};
  a.stages = {up};
  p.agents = {a};
  Obstacle o;  // a block in the way at low height, none up at the stage's height
  o.name = "block";
  o.vertices = box(-0.5, -0.5, 0.5, 0.5);
  o.is_box = true;
  o.z_lo = 1.5;
  o.z_hi = 2.5;
  p.obstacles = {o};
  MissionSchedule visits;
  visits.visit = {{30}};
  visits.horizon = 80;
  // Straight up from (0, 0, 0.5) to (0, 0, 3.3) crosses the block: the first leg is routed
  // (round the block), the second (from (0, 0, 3.3) down to the goal) is not: it starts above it.
  const auto w = route_waypoints(p, 80, visits);
  ASSERT_FALSE(w.empty());
  for (const auto& wp : w) EXPECT_LT(wp.step, 30);
}

namespace {

Prism block(double x0, double y0, double z0, double x1, double y1, double z1) { return {box(x0, y0, x1, y1), z0, z1}; }

// A wall at x in [2, 2.3] across the box [-1, 5] x [-3, 3] x [0, 3] and beyond it (a route
// along the box's faces would only touch it), with an opening y in [-0.5, 0.5], z in [1, 1.8].
std::vector<Prism> wall_with_window(double sill = 1.0) {
  return {block(2, -4, -1, 2.3, -0.5, 4), block(2, 0.5, -1, 2.3, 4, 4), block(2, -0.5, -1, 2.3, 0.5, sill),
          block(2, -0.5, 1.8, 2.3, 0.5, 4)};
}

bool inside(const Prism& p, const Eigen::Vector3d& q) {
  Eigen::Vector2d lo = p.base[0], hi = p.base[2];
  return q.x() > lo.x() + 1e-9 && q.x() < hi.x() - 1e-9 && q.y() > lo.y() + 1e-9 && q.y() < hi.y() - 1e-9 &&
         q.z() > p.z_lo + 1e-9 && q.z() < p.z_hi - 1e-9;
}

// Every point of the polyline (sampled densely) outside every block's interior.
void expect_clear(const std::vector<Prism>& prisms, const Eigen::Vector3d& a, const std::vector<Eigen::Vector3d>& corners,
                  const Eigen::Vector3d& b) {
  std::vector<Eigen::Vector3d> all{a};
  all.insert(all.end(), corners.begin(), corners.end());
  all.push_back(b);
  for (size_t s = 0; s + 1 < all.size(); ++s)
    for (int k = 0; k <= 2000; ++k) {
      const Eigen::Vector3d q = all[s] + (all[s + 1] - all[s]) * (k / 2000.0);
      for (const auto& p : prisms) ASSERT_FALSE(inside(p, q)) << q.transpose() << " on leg " << s;
    }
}

}  // namespace

TEST(RoutesInSpace, ThroughTheWindowOfAWall) {
  const auto wall = wall_with_window();
  const Eigen::Vector3d from(0, -1, 0.5), to(4.5, 1, 0.5), lo(-1, -3, 0), hi(5, 3, 3);
  bool found = false;
  const auto r = route_in_space(wall, lo, hi, from, to, &found);
  ASSERT_TRUE(found);
  ASSERT_FALSE(r.empty());
  expect_clear(wall, from, r, to);
  // It crosses the wall's plane inside the opening, and it climbs no higher than it must.
  for (const auto& c : r) {
    EXPECT_GE(c.z(), 1.0 - 1e-9);
    EXPECT_LE(c.z(), 1.8 + 1e-9);
    if (c.x() >= 2 && c.x() <= 2.3) EXPECT_LE(std::abs(c.y()), 0.5 + 1e-9);
  }
  double L = 0;
  Eigen::Vector3d p = from;
  for (const auto& c : r) L += (c - p).norm(), p = c;
  L += (to - p).norm();
  // Through the window's lower edge: about 4.9 (the straight line is 4.93 long but blocked).
  EXPECT_LT(L, 5.6);
}

TEST(RoutesInSpace, AClosedWindowHasNoRoute) {
  bool found = true;
  EXPECT_TRUE(route_in_space(wall_with_window(1.8), {-1, -3, 0}, {5, 3, 3}, {0, -1, 0.5}, {4.5, 1, 0.5}, &found).empty());
  EXPECT_FALSE(found);
}

TEST(RoutesInSpace, OverALowBlockWhenThatIsShorter) {
  // A block 0.4 high and 8 wide: over it is far shorter than around it.
  const std::vector<Prism> low{block(1, -4, 0, 2, 4, 0.4)};
  bool found = false;
  const auto r = route_in_space(low, {-1, -5, 0}, {4, 5, 2}, {0, 0, 0.2}, {3, 0, 0.2}, &found);
  ASSERT_TRUE(found);
  ASSERT_EQ(r.size(), 2u);
  for (const auto& c : r) EXPECT_NEAR(c.z(), 0.4, 1e-5);  // a hair above the top (the lattice's planes)
  expect_clear(low, {0, 0, 0.2}, r, {3, 0, 0.2});
}

TEST(RoutesInSpace, AFreeSegmentNeedsNoCornerAndAnEndInsideHasNoRoute) {
  bool found = false;
  EXPECT_TRUE(route_in_space({block(1, 1, 0, 2, 2, 1)}, {-1, -1, 0}, {4, 4, 3}, {0, 0, 0.5}, {3, 0, 0.5}, &found).empty());
  EXPECT_TRUE(found);
  // Just over the top.
  EXPECT_TRUE(route_in_space({block(1, -1, 0, 2, 1, 1)}, {-1, -2, 0}, {4, 2, 3}, {0, 0, 1.01}, {3, 0, 1.01}, &found).empty());
  EXPECT_TRUE(found);
  EXPECT_TRUE(route_in_space({block(1, -1, 0, 2, 1, 1)}, {-1, -2, 0}, {4, 2, 3}, {1.5, 0, 0.5}, {3, 0, 1}, &found).empty());
  EXPECT_FALSE(found);
}

TEST(RoutesInSpace, WaypointsPinAllThreeCoordinates) {
  Problem p;
  p.delta = 0.2;
  p.delta_norm = Norm::Inf;
  AgentSpec a;
  a.name = "drone";
  a.x0 = Eigen::Vector3d(0, -1, 0.5);
  a.goal = {Eigen::Vector3d(4.3, 0.8, 0.3), Eigen::Vector3d(4.7, 1.2, 0.7)};
  a.state_bounds = {Eigen::Vector3d(-1, -3, 0), Eigen::Vector3d(5, 3, 3)};
  a.input_bounds = {Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1)};
  a.tube.eps = Eigen::Vector3d(0.05, 0.05, 0.05);
  a.tube.w = Eigen::Vector3d::Zero();
  a.workspace.index = {0, 1, 2};
  a.workspace.offset = {0, 0, 0};
  p.agents = {a};
  for (const auto& w : wall_with_window()) {
    Obstacle o;
    o.name = "part";
    o.vertices = w.base;
    o.is_box = true;
    o.z_lo = w.z_lo;
    o.z_hi = w.z_hi;
    p.obstacles.push_back(o);
  }
  const auto ways = route_waypoints(p, 80);
  ASSERT_FALSE(ways.empty());
  for (const auto& w : ways) {
    ASSERT_EQ(w.x.size(), 3);
    EXPECT_TRUE(w.x.allFinite());
    // Grown by 1.1 (delta + eps) = 0.275: inside the window less that, i.e. z in [1.275, 1.525].
    EXPECT_GE(w.x[2], 1.275 - 1e-9);
    EXPECT_LE(w.x[2], 1.525 + 1e-9);
  }
}

// Another homotopy class: a wall from inside the first obstacle out past everything on the side
// the shortest route takes, so the route around both passes the obstacle on the other side.
TEST(RoutesOtherSide, BesideABoxTheOtherWayRound) {
  const std::vector<Prism> one{{box(4, -1, 6, 1.2), -INFINITY, INFINITY}};
  const Eigen::Vector3d from(0, 0, 0), to(10, 0, 0);
  std::vector<Polygon> polygons{one[0].base};
  const auto shortest = shortest_route(polygons, from.head<2>(), to.head<2>());
  ASSERT_EQ(shortest.size(), 2u);
  EXPECT_EQ(shortest[0].y(), -1.0);  // under the box: it reaches less far down
  std::vector<Eigen::Vector3d> corners;
  for (const auto& c : shortest) corners.push_back({c.x(), c.y(), 0.0});
  const auto wall = other_side_barrier(one, from, to, corners, 100);
  ASSERT_TRUE(wall.has_value());
  polygons.push_back(wall->base);
  const auto other = shortest_route(polygons, from.head<2>(), to.head<2>());
  ASSERT_EQ(other.size(), 2u);
  for (const auto& c : other) EXPECT_EQ(c.y(), 1.2);  // over the box now
  // A straight way that crosses nothing has no other side.
  EXPECT_FALSE(other_side_barrier(one, {0, 5, 0}, {10, 5, 0}, {{5, 5, 0}}, 100).has_value());
}

TEST(RoutesOtherSide, OverALowBlockBecomesAroundIt) {
  const std::vector<Prism> low{block(1, -1, 0, 2, 1, 0.4)};
  const Eigen::Vector3d from(0, 0, 0.2), to(3, 0, 0.2), lo(-1, -3, 0), hi(4, 3, 2);
  const auto over = route_in_space(low, lo, hi, from, to);
  ASSERT_FALSE(over.empty());
  for (const auto& c : over) EXPECT_NEAR(c.z(), 0.4, 1e-5);
  const auto wall = other_side_barrier(low, from, to, over, 100);
  ASSERT_TRUE(wall.has_value());
  std::vector<Prism> walled = low;
  walled.push_back(*wall);
  bool found = false;
  const auto around = route_in_space(walled, lo, hi, from, to, &found);
  ASSERT_TRUE(found);
  ASSERT_FALSE(around.empty());
  expect_clear(walled, from, around, to);
  for (const auto& c : around) EXPECT_LT(c.z(), 0.4);         // below the top: beside the block
  EXPECT_GE(std::abs(around[0].y()), 1.0 - 1e-5);
}

TEST(RoutesOtherSide, WaypointsForTheListedAgentOnly) {
  Problem p;
  p.delta = 0.2;
  p.delta_norm = Norm::Inf;
  auto agent = [](const std::string& name, double y) {
    AgentSpec a;
    a.name = name;
    a.x0 = Eigen::Vector2d(0, y);
    a.goal = {Eigen::Vector2d(9.5, y - 0.5), Eigen::Vector2d(10.5, y + 0.5)};
    a.state_bounds = {Eigen::Vector2d(-1, -5), Eigen::Vector2d(11, 5)};
    a.input_bounds = {Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1)};
    a.tube.eps = Eigen::Vector2d(0.1, 0.1);
    a.tube.w = Eigen::Vector2d(0, 0);
    return a;
  };
  p.agents = {agent("a", 0.3), agent("b", 0.2)};
  Obstacle o;
  o.name = "block";
  o.vertices = box(4, -1, 6, 1);
  o.is_box = true;
  p.obstacles = {o};
  // Both pass over the block (their lines run above its middle); b on the other side passes under.
  for (const auto& w : route_waypoints(p, 100)) EXPECT_GT(std::isfinite(w.x[1]) ? w.x[1] : w.x[3], 1.0);
  int a_over = 0, b_under = 0;
  for (const auto& w : route_waypoints(p, 100, {}, {1})) {
    if (std::isfinite(w.x[1])) a_over += w.x[1] > 1.0;
    if (std::isfinite(w.x[3])) b_under += w.x[3] < -1.0;
  }
  EXPECT_EQ(a_over, 2);
  EXPECT_EQ(b_under, 2);
  // A lane closed on the other side (the block reaching the bounds below): the shortest route stays.
  p.obstacles[0].vertices = box(4, -6, 6, 1);
  for (const auto& w : route_waypoints(p, 100, {}, {1}))
    if (std::isfinite(w.x[3])) EXPECT_GT(w.x[3], 1.0);
}

// 160 blocks give a lattice of millions of points at their planes alone: the planes are thinned
// to fit, and the route found is still clear of every block (every lattice edge checked exactly).
TEST(RoutesInSpace, ManyBlocksThinTheLatticeAndTheRouteStaysClear) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Prism> blocks;
  for (int i = 0; i < 160; ++i) {
    const double x = 2 + 7 * u(rng), y = 1 + 9 * u(rng), z = 3 * u(rng), s = 0.3 + 0.6 * u(rng);
    blocks.push_back(block(x, y, z, x + s, y + s, z + s));
  }
  const Eigen::Vector3d from(0.5, 6, 2), to(11.5, 6, 2);
  bool found = false;
  const auto r = route_in_space(blocks, {0, 0, 0}, {12, 12, 4}, from, to, &found);
  ASSERT_TRUE(found);
  ASSERT_FALSE(r.empty());
  expect_clear(blocks, from, r, to);
}

// Walls reaching the agent's position bounds: the route stays inside the bounds (less the
// margin) and bends round each wall's open end, not round its end beyond the bounds.
TEST(Routes, RoutesStayInsideThePositionBounds) {
  Problem p = one_walker("robot", {1, 2}, {10, 8}, {0, 0}, {12, 10});
  Obstacle low, high;
  low.name = "low";
  low.vertices = box(3, 0, 3.3, 8);  // open at the north end (round its south end beyond the bounds is shorter)
  low.is_box = true;
  high.name = "high";
  high.vertices = box(6.5, 2, 6.8, 10);  // open at the south end
  high.is_box = true;
  p.obstacles = {low, high};
  const auto w = route_waypoints(p, 100);
  ASSERT_EQ(w.size(), 4u);
  EXPECT_GT(w[0].x[1], 8.0);  // round low's north end
  EXPECT_GT(w[1].x[1], 8.0);
  EXPECT_LT(w[2].x[1], 2.0);  // round high's south end
  EXPECT_LT(w[3].x[1], 2.0);
  for (const auto& wp : w) {
    EXPECT_GE(wp.x[1], 0.0);
    EXPECT_LE(wp.x[1], 10.0);
  }
}
