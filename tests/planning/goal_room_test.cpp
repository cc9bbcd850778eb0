// Goals that leave no room for the tubes (planning/goal_room): found exactly where no point of
// the shrunk goal keeps the robust margin (checked against a dense sampling of the goal with the
// specification's own margins), with the factor on eps that frees them; goals with room, and
// agents with a footprint, are left alone.
#include <gtest/gtest.h>

#include "marsyn/core/planning/goal_room.hpp"
#include "marsyn/core/planning/margins.hpp"
#include "marsyn/core/planning/spec_margins.hpp"
#include "../support/message_style.hpp"

using namespace marsyn;
using namespace marsyn::planning;

namespace {

Obstacle box(const std::string& name, double x0, double y0, double x1, double y1) {
  Obstacle o;
  o.name = name;
  o.vertices = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  o.is_box = true;
  return o;
}

AgentSpec agent(const std::string& name, double gx, double gy, double eps) {
  AgentSpec a;
  a.name = name;
  a.x0 = Eigen::Vector3d(0, gy, 0);
  a.state_bounds = {Eigen::Vector3d(-1, -1, -3), Eigen::Vector3d(11, 11, 3)};
  a.goal = {Eigen::Vector3d(gx - 0.2, gy - 0.2, -0.6), Eigen::Vector3d(gx + 0.2, gy + 0.2, 0.6)};
  a.tube.eps = Eigen::Vector3d(eps, eps, 0.3);
  a.workspace.index = {0, 1};
  return a;
}

// A goal (radius 0.2) centred at gx beside a wall at x = 5.25, delta 0.15, eps 0.15: the end
// farthest from the wall, x = gx - 0.2 + 0.15 f at eps x f, keeps 5.25 - x - 0.15 f - 0.15 =
// 5.3 - gx - 0.3 f (the tube's box grows the wall by 0.15 f in x, in both norms).
Problem dock(double gx, Norm norm) {
  Problem p;
  p.delta = 0.15;
  p.delta_norm = norm;
  p.horizon = 60;
  p.agents = {agent("a", gx, 1.0, 0.15)};
  p.obstacles = {box("wall", 5.25, 0, 5.6, 5)};
  return p;
}

// The best robust margin over a dense grid of the shrunk goal's workspace points: what the
// diagnosis claims is the largest value there.
double sampled_room(const Problem& p, const AgentSpec& a) {
  const WorkspaceMargin m = margin_at(a, a.goal.center());
  double best = -1e300;
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 40; ++j) {
      const double x = a.goal.lo[0] + a.tube.eps[0] + (a.goal.hi[0] - a.goal.lo[0] - 2 * a.tube.eps[0]) * i / 40;
      const double y = a.goal.lo[1] + a.tube.eps[1] + (a.goal.hi[1] - a.goal.lo[1] - 2 * a.tube.eps[1]) * j / 40;
      best = std::max(best, obstacle_margin(p.obstacles[0].vertices, Eigen::Vector2d(x, y), m, p.delta, p.delta_norm));
    }
  return best;
}

}  // namespace

TEST(GoalRoom, AGoalBesideAWallIsFoundWithTheFactorThatFreesIt) {
  for (Norm norm : {Norm::Inf, Norm::Two}) {
    const Problem p = dock(5.05, norm);
    const auto c = crowded_goals(p);
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c[0].agent, "a");
    EXPECT_EQ(c[0].other, "obstacle wall");
    EXPECT_NEAR(c[0].room, -0.05, 1e-9);
    EXPECT_NEAR(c[0].room, sampled_room(p, p.agents[0]), 1e-9);  // the corners are the best points
    EXPECT_NEAR(c[0].eps_factor, 0.25 / 0.3, 1e-8);
    EXPECT_NEAR(goal_eps_factor(p), 0.25 / 0.3, 1e-8);
    const std::string text = describe(c[0], p);
    EXPECT_NE(text.find("a's goal leaves no room for its tube beside obstacle wall"), std::string::npos) << text;
    EXPECT_NE(text.find("no horizon can help; eps x 0.83 or less"), std::string::npos) << text;
    EXPECT_EQ(marsyn::test::style_report(text), "");  // it used to stop at "... would"

    // Just below the factor the goal has room; just above it has none.
    Problem q = p;
    q.agents[0].tube.eps *= 0.99 * c[0].eps_factor;
    EXPECT_TRUE(crowded_goals(q).empty());
    EXPECT_GT(sampled_room(q, q.agents[0]), 0.0);
    q.agents[0].tube.eps = p.agents[0].tube.eps * 1.01 * c[0].eps_factor;
    EXPECT_EQ(crowded_goals(q).size(), 1u);
  }
}

TEST(GoalRoom, ExactlyNoRoomCountsAsNone) {
  // gx = 5: room 0.3 - 0.3 f, exactly 0 at the written eps; the planner cannot end on the boundary.
  const auto c = crowded_goals(dock(5.0, Norm::Inf));
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].room, 0.0, 1e-12);
  EXPECT_NEAR(c[0].eps_factor, 1.0, 1e-8);
  EXPECT_LT(c[0].eps_factor, 1.0);
  EXPECT_NE(describe(c[0], dock(5.0, Norm::Inf)).find("is at most 0:"), std::string::npos);
}

TEST(GoalRoom, GoalsWithRoomAndFootprintsAreLeftAlone) {
  EXPECT_TRUE(crowded_goals(dock(4.9, Norm::Inf)).empty());  // room 0.1
  Problem p = dock(5.05, Norm::Inf);
  p.agents[0].workspace.footprint = 0;  // a nonlinear footprint: not judged
  EXPECT_TRUE(crowded_goals(p).empty());
  EXPECT_EQ(goal_eps_factor(p), 1.0);
}

TEST(GoalRoom, TwoGoalsTooCloseForBothTubes) {
  Problem p;
  p.delta = 0.24;
  p.delta_norm = Norm::Inf;
  p.horizon = 40;
  // Goals 0.3 apart in y, radius 0.2, eps 0.15: the farthest ends are 0.3 + 2 (0.2 - 0.15 f) apart
  // and need 0.24 + 2 (0.15 f): room 0.46 - 0.6 f, 0 at f = 0.7667.
  p.agents = {agent("low", 3, 0, 0.15), agent("high", 3, 0.3, 0.15)};
  const auto c = crowded_goals(p);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].agent, "low");
  EXPECT_EQ(c[0].other, "high");
  EXPECT_NEAR(c[0].room, -0.14, 1e-9);
  EXPECT_NEAR(c[0].eps_factor, 0.46 / 0.6, 1e-8);
  p.pairwise_collision = false;
  EXPECT_TRUE(crowded_goals(p).empty());
}

TEST(GoalRoom, InSpaceTheHeightCounts) {
  // A hover goal under a slab (z in [1, 2] over x, y in [4, 6] x [-1, 3]): the goal's lowest end,
  // z = 0.6 + 0.15 f at eps x f, keeps 1 - 0.15 f - z - 0.15 = 0.25 - 0.3 f from delta plus the tube.
  Problem p;
  p.delta = 0.15;
  p.delta_norm = Norm::Two;
  p.horizon = 60;
  AgentSpec a = agent("drone", 5, 1, 0.15);
  a.goal.lo[2] = 0.6;
  a.goal.hi[2] = 1.0;
  a.tube.eps[2] = 0.15;
  a.workspace.index = {0, 1, 2};
  a.workspace.offset = {0, 0, 0};
  p.agents = {a};
  Obstacle slab = box("slab", 4, -1, 6, 3);
  slab.z_lo = 1.0;
  slab.z_hi = 2.0;
  p.obstacles = {slab};
  auto c = crowded_goals(p);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].room, -0.05, 1e-9);
  EXPECT_NEAR(c[0].eps_factor, 0.25 / 0.3, 1e-8);
  p.obstacles[0].z_lo = 1.1;  // 0.1 higher: room 0.05
  EXPECT_TRUE(crowded_goals(p).empty());
}
