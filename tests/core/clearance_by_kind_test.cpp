// `delta` by kind (issue 51): `delta: {agents: a, obstacles: o}` keeps agents a apart and o from
// the obstacles; a number stays one clearance for both.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "marsyn/core/planning/workspace_gaps.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/solve.hpp"
#include "quick_solve.hpp"

namespace {

std::string file(const std::string& name) { return std::string(MARSYN_SOURCE_DIR) + "/tests/continuous/" + name; }

std::string variant(const std::string& from, const std::string& to, const std::string& tag) {
  std::ifstream in(file("clearance_by_kind.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  s.replace(s.find(from), from.size(), to);
  const std::string path = testing::TempDir() + "clearance_" + tag + ".yaml";
  std::ofstream(path) << s;
  return path;
}

double inf_distance_to_box(double x, double y, double x0, double y0, double x1, double y1) {
  return std::max({x0 - x, x - x1, y0 - y, y - y1, 0.0});
}

}  // namespace

TEST(ClearanceByKind, TheLoaderReadsBothKindsAndANumberStaysOne) {
  const auto both = marsyn::load_problem(file("clearance_by_kind.yaml"));
  EXPECT_DOUBLE_EQ(both.problem.delta, 0.8);
  EXPECT_DOUBLE_EQ(both.problem.obstacle_delta(), 0.2);
  const auto one = marsyn::load_problem(variant("delta: {agents: 0.8, obstacles: 0.2}", "delta: 0.8", "one"));
  EXPECT_DOUBLE_EQ(one.problem.delta, 0.8);
  EXPECT_DOUBLE_EQ(one.problem.obstacle_delta(), 0.8);
  // A start 0.3 from a wall: accepted under the walls' own 0.2, refused under 0.4 (naming it).
  std::string moved = variant("x0: [1.5, 0, 0]", "x0: [3.5, 0.7, 0]", "near");
  EXPECT_NO_THROW(marsyn::load_problem(moved));
  std::ifstream in(moved);
  std::stringstream t;
  t << in.rdbuf();
  std::string s = t.str();
  s.replace(s.find("obstacles: 0.2}"), 15, "obstacles: 0.4}");
  std::ofstream(moved) << s;
  try {
    marsyn::load_problem(moved);
    ADD_FAILURE() << "a start 0.3 from a wall passed with the walls' delta 0.4";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("less than delta's obstacles = 0.4"), std::string::npos) << e.what();
  }
}

// The doorway is 1.2 wide: closed under one delta of 0.8, open under the walls' own 0.2. The team
// verifies; its plan keeps the agents 0.8 (+ both eps) apart and passes the walls closer than 0.8.
TEST(ClearanceByKind, EachKindKeepsItsOwnClearance) {
  const auto lp = marsyn::load_problem(file("clearance_by_kind.yaml"));
  const marsyn::SolveOutcome o = marsyn::solve(lp, marsyn::test::quick_solve());
  ASSERT_TRUE(o.verified) << o.failure;
  const auto& n = o.plan.nominal;
  ASSERT_EQ(n.size(), 2u);
  double pair = 1e9, wall = 1e9;
  for (std::size_t k = 0; k < n[0].x.size(); ++k) {
    const auto &a = n[0].x[k], &b = n[1].x[k];
    pair = std::min(pair, std::max(std::abs(a[0] - b[0]), std::abs(a[1] - b[1])));
    for (const auto* x : {&a, &b})
      wall = std::min({wall, inf_distance_to_box((*x)[0], (*x)[1], 3.8, -3.5, 4.2, -0.6),
                       inf_distance_to_box((*x)[0], (*x)[1], 3.8, 0.6, 4.2, 3.5)});
  }
  EXPECT_GE(pair, 0.8 + 0.2 - 1e-9);  // delta between agents plus both tubes
  EXPECT_GE(wall, 0.2 + 0.1 - 1e-9);  // the walls' delta plus the tube
  EXPECT_LT(wall, 0.8);               // through the doorway: closer than the agents' delta
  // The doorway's gap: open with the walls' own delta, closed under one delta of 0.8 for both.
  EXPECT_TRUE(marsyn::planning::narrow_gaps(lp.problem).empty());
  const auto one = marsyn::load_problem(variant("delta: {agents: 0.8, obstacles: 0.2}", "delta: 0.8", "closed"));
  const auto gaps = marsyn::planning::narrow_gaps(one.problem);
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0].first, "obstacle wall_south");
  EXPECT_NEAR(gaps[0].needed, 1.8, 1e-9);
}
