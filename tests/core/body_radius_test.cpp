// Bodies of their own size (issue 51): an agent's `radius` is added to every clearance it keeps
// (pairwise between two agents), and `delta: {bounds: b}` with the radius keeps the body inside
// the state bounds of its position. Every reader takes the same sums: the loader, the planner's
// rows, the exact check, the certifier's boxes, the closed-loop monitor, the gaps and the starts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

#include "marsyn/core/planning/box_margins.hpp"
#include "marsyn/core/planning/constraints.hpp"
#include "marsyn/core/planning/spec_margins.hpp"
#include "marsyn/core/planning/workspace_gaps.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/problem/problem_summary.hpp"
#include "marsyn/core/solve.hpp"
#include "load_error.hpp"
#include "problem_variant.hpp"
#include "quick_solve.hpp"
#include "side_by_side.hpp"

namespace {

using marsyn::test::load_error;

std::string base_file() { return std::string(MARSYN_SOURCE_DIR) + "/tests/continuous/clearance_by_kind.yaml"; }

std::string variant(const std::vector<std::pair<std::string, std::string>>& edits, const std::string& tag) {
  return marsyn::test::problem_variant(base_file(), edits, "body_" + tag);
}

// The second robot with its own radius r (the first keeps none).
std::string second_with_radius(double r, const std::string& tag) {
  std::ostringstream to;
  to << "  - name: second\n    radius: " << r << "\n";
  return variant({{"  - name: second\n", to.str()}}, tag);
}

double inf_distance_to_box(double x, double y, double x0, double y0, double x1, double y1) {
  return std::max({x0 - x, x - x1, y0 - y, y - y1, 0.0});
}

marsyn::CertificationReport certify_side_by_side(double r0, double r1) {
  marsyn::Problem pb = marsyn::test::side_by_side(0.8, 0.2);
  pb.agents[0].radius = r0;
  pb.agents[1].radius = r1;
  return marsyn::test::certify_side_by_side(pb);
}

}  // namespace

// The certifier subtracts each requirement's own clearance: the pair keeps 1.0 - 0.1 = 0.9 >= 0.8
// and the first robot 0.85 >= 0.2 from the wall; radii of 0.06 each take the pair below (0.92),
// a radius of 0.7 on the first takes the wall below (0.9), and the pair with it.
TEST(BodyRadius, TheCertifierHoldsEachRequirementToItsOwnBodies) {
  const auto none = certify_side_by_side(0, 0);
  EXPECT_TRUE(none.certified) << none.message;
  EXPECT_NEAR(none.collision.margin, 0.1, 1e-9);
  EXPECT_NEAR(none.obstacle.margin, 0.65, 1e-9);
  const auto pair = certify_side_by_side(0.06, 0.06);
  EXPECT_FALSE(pair.certified);
  EXPECT_NEAR(pair.collision.margin, -0.02, 1e-9);
  EXPECT_EQ(pair.collision.where, "collision a vs b");
  EXPECT_NEAR(pair.obstacle.margin, 0.59, 1e-9);
  const auto wall = certify_side_by_side(0.7, 0.0);
  EXPECT_FALSE(wall.certified);
  EXPECT_NEAR(wall.obstacle.margin, -0.05, 1e-9);
  EXPECT_EQ(wall.obstacle.where, "obstacle wall vs a");
  EXPECT_NEAR(wall.collision.margin, -0.6, 1e-9);  // 0.9 - 0.8 - 0.7: the pair holds the first's body too
}

TEST(BodyRadius, TheLoaderPullsThePositionBoundsInByTheBodysClearance) {
  const auto plain = marsyn::load_problem(base_file());
  EXPECT_DOUBLE_EQ(plain.problem.agents[0].radius, 0.0);
  EXPECT_DOUBLE_EQ(plain.problem.agents[0].state_bounds.lo[0], -1.0);  // unchanged without a body
  const auto lp = marsyn::load_problem(variant(
      {{"delta: {agents: 0.8, obstacles: 0.2}", "delta: {agents: 0.8, obstacles: 0.2, bounds: 0.1}"},
       {"  workspace: {position: [0, 1]}", "  workspace: {position: [0, 1]}\n  radius: 0.25"}},
      "defaults"));
  const marsyn::Problem& pb = lp.problem;
  EXPECT_DOUBLE_EQ(pb.delta_bounds, 0.1);
  for (const auto& a : pb.agents) {
    EXPECT_DOUBLE_EQ(a.radius, 0.25);
    EXPECT_DOUBLE_EQ(a.state_bounds.lo[0], -1.0 + 0.35);
    EXPECT_DOUBLE_EQ(a.state_bounds.hi[0], 9.0 - 0.35);
    EXPECT_DOUBLE_EQ(a.state_bounds.lo[1], -3.0 + 0.35);
    EXPECT_DOUBLE_EQ(a.state_bounds.hi[1], 3.0 - 0.35);
    EXPECT_DOUBLE_EQ(a.state_bounds.lo[2], -4.0);  // the heading is not a position
  }
  EXPECT_DOUBLE_EQ(pb.pair_clearance(0, 1), 0.8 + 0.25 + 0.25);
  EXPECT_DOUBLE_EQ(pb.obstacle_clearance(1), 0.2 + 0.25);
  const std::string text = marsyn::summarize(pb);
  EXPECT_NE(text.find("0.1 to the state bounds"), std::string::npos) << text;
  EXPECT_NE(text.find("bodies    first, second: radius 0.25"), std::string::npos) << text;
}

TEST(BodyRadius, BadBodiesAreLocatedErrors) {
  std::string e = load_error(second_with_radius(-0.1, "negative"));
  EXPECT_NE(e.find("agents[1].radius"), std::string::npos) << e;
  // y runs over [-3, 3]: a body of 3 leaves no room in it.
  e = load_error(second_with_radius(3, "huge"));
  EXPECT_NE(e.find("leave no room for second's body"), std::string::npos) << e;
  EXPECT_NE(e.find("agents[1].radius"), std::string::npos) << e;
  EXPECT_NE(e.find("'y'"), std::string::npos) << e;
  // The second robot starts at x = 0, inside [-1, 9]; a body of 0.95 pulls the bounds to [-0.05, 8.05],
  // so that its tube (eps 0.1) leaves them: the message says why the numbers differ from the file's.
  e = load_error(second_with_radius(0.95, "tube"));
  EXPECT_NE(e.find("less the body's clearance 0.95"), std::string::npos) << e;
  // Two starts 1.5 apart keep delta 0.8, not delta plus a radius of 0.8.
  e = load_error(second_with_radius(0.8, "starts"));
  EXPECT_NE(e.find("plus their radii 0.8 and 0 = 1.6"), std::string::npos) << e;
  e = load_error(variant({{"delta: {agents: 0.8, obstacles: 0.2}", "delta: {agents: 0.8, obstacles: 0.2, bounds: -1}"}},
                         "bounds"));
  EXPECT_NE(e.find("delta.bounds"), std::string::npos) << e;
}

// The exact margins, the certifier's box margins (a point is a box of width 0) and the plain
// sums agree for random points and radii.
TEST(BodyRadius, EveryReaderTakesTheSameClearance) {
  auto lp = marsyn::load_problem(base_file());
  marsyn::Problem& pb = lp.problem;
  std::mt19937_64 rng(51);
  std::uniform_real_distribution<double> c(-3, 9), r(0.0, 0.6);
  for (int t = 0; t < 2000; ++t) {
    pb.agents[0].radius = r(rng);
    pb.agents[1].radius = t % 3 == 0 ? 0.0 : r(rng);
    pb.delta_norm = t % 2 ? marsyn::Norm::Two : marsyn::Norm::Inf;
    const marsyn::planning::Point p(c(rng), c(rng), 0), q(c(rng), c(rng), 0);
    const std::vector<marsyn::planning::Point> pts{p, q};
    std::vector<marsyn::Box> boxes;
    for (const auto& s : pts) boxes.push_back({Eigen::Vector2d(s.x(), s.y()), Eigen::Vector2d(s.x(), s.y())});
    const Eigen::Vector2d d(p.x() - q.x(), p.y() - q.y());
    const double dist = pb.delta_norm == marsyn::Norm::Inf ? d.cwiseAbs().maxCoeff() : d.norm();
    const marsyn::planning::Requirement pair{marsyn::planning::Requirement::Collision, 0, 1};
    const double exact = marsyn::planning::requirement_margin(pb, pair, pts);
    EXPECT_NEAR(exact, dist - (0.8 + pb.agents[0].radius + pb.agents[1].radius), 1e-12);
    const double boxed = marsyn::planning::box_requirement_margin(pb, pair, boxes);
    EXPECT_NEAR(boxed, exact, 1e-12);
    // The south wall, for each agent with its own radius.
    for (int i = 0; i < 2; ++i) {
      const marsyn::planning::Requirement wall{marsyn::planning::Requirement::Obstacle, i, 0};
      const double e = marsyn::planning::requirement_margin(pb, wall, pts);
      const double b = marsyn::planning::box_requirement_margin(pb, wall, boxes);
      EXPECT_NEAR(b, e, 1e-12);
      const bool inside = pts[i].x() > 3.8 && pts[i].x() < 4.2 && pts[i].y() > -3.5 && pts[i].y() < -0.6;
      if (pb.delta_norm == marsyn::Norm::Inf && !inside)
        EXPECT_NEAR(e, inf_distance_to_box(pts[i].x(), pts[i].y(), 3.8, -3.5, 4.2, -0.6) - (0.2 + pb.agents[i].radius),
                    1e-12);
    }
  }
}

// The planner's rows with bodies are the rows of bodiless agents keeping the sums: a pair's with
// delta + r_a + r_b, an agent's obstacle rows with the obstacles' delta + its radius.
TEST(BodyRadius, ThePlannersRowsKeepTheSums) {
  auto lp = marsyn::load_problem(base_file());
  marsyn::Problem bodies = lp.problem;
  bodies.agents[0].radius = 0.3;
  bodies.agents[1].radius = 0.2;
  auto rows = [](const marsyn::Problem& pb) {
    std::map<std::string, std::shared_ptr<const marsyn::Constraint>> out;
    for (const auto& c : marsyn::planning::assemble(pb, pb.horizon).constraints) out[c->name()] = c;
    return out;
  };
  const auto with = rows(bodies);
  marsyn::Problem pair = lp.problem, first = lp.problem, second = lp.problem;
  pair.delta = 0.8 + 0.3 + 0.2;
  first.delta_obstacles = 0.2 + 0.3;
  second.delta_obstacles = 0.2 + 0.2;
  const auto p = rows(pair), f = rows(first), s = rows(second);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> c(-1, 9);
  int compared = 0;
  for (const auto& [name, row] : with) {
    const auto& same = name.rfind("collision", 0) == 0                        ? p
                       : name.rfind("obstacle", 0) == 0 && name.find("vs first") != std::string::npos ? f
                       : name.rfind("obstacle", 0) == 0                       ? s
                                                                              : with;
    if (&same == &with) continue;
    const auto& other = same.at(name);
    const int n = bodies.product_state_dim();
    for (int t = 0; t < 50; ++t) {
      std::vector<double> x(static_cast<std::size_t>(n));
      for (auto& v : x) v = c(rng);
      std::vector<double> g(static_cast<std::size_t>(row->size())), h(g.size());
      row->evaluate(x.data(), g.data(), nullptr);
      other->evaluate(x.data(), h.data(), nullptr);
      for (std::size_t r = 0; r < g.size(); ++r) ASSERT_NEAR(g[r], h[r], 1e-12) << name;
    }
    ++compared;
  }
  EXPECT_GE(compared, 5);  // a pair and two walls for each robot
}

// A radius counts for its own agent's requirements only: the doorway (1.2 wide across y) needs 2 (0.2 +
// r + 0.1) of the second robot, open at r = 0.2 (1.0), closed at r = 0.35 (1.3), and to it alone.
TEST(BodyRadius, ARadiusClosesAGapToItsOwnAgentOnly) {
  const auto open = marsyn::load_problem(second_with_radius(0.2, "open"));
  EXPECT_TRUE(marsyn::planning::narrow_gaps(open.problem).empty());
  const auto closed = marsyn::load_problem(second_with_radius(0.35, "closed"));
  const auto gaps = marsyn::planning::narrow_gaps(closed.problem);
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0].agents, std::vector<std::string>{"second"});
  EXPECT_NEAR(gaps[0].needed, 1.3, 1e-9);
  const std::string text = marsyn::planning::describe(gaps[0]);
  EXPECT_NE(text.find("2 (delta + radius + eps in y)"), std::string::npos) << text;
}

// The team verifies with the second robot's body; the plan keeps the pair 0.8 + 0.2 (the radius)
// + 0.2 (both tubes) apart and the second robot 0.2 + 0.2 + 0.1 from the walls, while the first
// (no body) passes them closer than that.
TEST(BodyRadius, ThePlanAndTheCertificateKeepTheBody) {
  const auto lp = marsyn::load_problem(second_with_radius(0.2, "solve"));
  const marsyn::SolveOutcome o = marsyn::solve(lp, marsyn::test::quick_solve());
  ASSERT_TRUE(o.verified) << o.failure;
  const auto& n = o.plan.nominal;
  ASSERT_EQ(n.size(), 2u);
  double pair = 1e9, wall[2] = {1e9, 1e9};
  for (std::size_t k = 0; k < n[0].x.size(); ++k) {
    const auto &a = n[0].x[k], &b = n[1].x[k];
    pair = std::min(pair, std::max(std::abs(a[0] - b[0]), std::abs(a[1] - b[1])));
    for (int i = 0; i < 2; ++i) {
      const auto& x = n[static_cast<std::size_t>(i)].x[k];
      wall[i] = std::min({wall[i], inf_distance_to_box(x[0], x[1], 3.8, -3.5, 4.2, -0.6),
                          inf_distance_to_box(x[0], x[1], 3.8, 0.6, 4.2, 3.5)});
    }
  }
  EXPECT_GE(pair, 0.8 + 0.2 + 0.2 - 1e-9);
  EXPECT_GE(wall[1], 0.2 + 0.2 + 0.1 - 1e-9);
  EXPECT_GE(wall[0], 0.2 + 0.1 - 1e-9);
  EXPECT_LT(wall[0], 0.2 + 0.2 + 0.1);  // the first robot has no body: it may pass closer
}
