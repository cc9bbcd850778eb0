// Agents with several bodies (issue 51 item 2, `bodies:`): a tractor and its cart, each a point of
// the rig's state with its own radius. The further bodies are body slots after the agents' first
// ones (Problem::body_count); every reader of the specification takes them: the planner's rows,
// the exact check, the certifier (their boxes from the enclosures' state boxes), the closed-loop
// monitor and its broad phase, the start checks and check's counts.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "marsyn/core/planning/spec_margins.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/problem/problem_summary.hpp"
#include "marsyn/core/solve.hpp"
#include "load_error.hpp"
#include "quick_solve.hpp"
#include "side_by_side.hpp"

namespace {

using marsyn::test::load_error;

const std::string kExample = std::string(MARSYN_SOURCE_DIR) + "/examples/tractor_trailer.yaml";

std::string slurp(const std::string& f) {
  std::ifstream in(f);
  std::stringstream t;
  t << in.rdbuf();
  return t.str();
}

std::string write(const std::string& text, const std::string& tag) {
  const std::string path = testing::TempDir() + "bodies_" + tag + ".yaml";
  std::ofstream(path) << text;
  return path;
}

std::string edited(const std::string& from, const std::string& to, const std::string& tag) {
  std::string s = slurp(kExample);
  const auto at = s.find(from);
  if (at == std::string::npos) throw std::runtime_error("no '" + from + "' in the example");
  s.replace(at, from.size(), to);
  return write(s, tag);
}

const std::string kBodies =
    "    bodies:\n"
    "      - {name: tractor, workspace: {position: [0, 1]}, radius: 0.8}\n"
    "      - {name: cart, workspace: {footprint: cart}, radius: 0.8}\n";

// The wall of the example, [9, 10] x [0, 8]: inf-norm distance, negative inside.
double wall_distance(double x, double y) {
  if (x >= 9 && x <= 10 && y >= 0 && y <= 8) return -std::min({x - 9, 10 - x, y, 8 - y});
  return std::max({9 - x, x - 10, -y, y - 8, 0.0});
}

// The closest the tractor's and the cart's points come to the wall along a plan.
std::pair<double, double> closest(const marsyn::planning::PlanOutcome& plan) {
  double tractor = 1e9, cart = 1e9;
  for (const auto& x : plan.nominal.at(0).x) {
    tractor = std::min(tractor, wall_distance(x[0], x[1]));
    cart = std::min(cart, wall_distance(x[0] - 2 * std::cos(x[2] - x[3]), x[1] - 2 * std::sin(x[2] - x[3])));
  }
  return {tractor, cart};
}

}  // namespace

TEST(AgentBodies, TheLoaderMakesABodySlotPerFurtherBody) {
  const auto lp = marsyn::load_problem(kExample);
  const marsyn::Problem& pb = lp.problem;
  ASSERT_EQ(pb.agents.size(), 1u);
  ASSERT_EQ(pb.body_count(), 2);
  EXPECT_EQ(pb.body_agent(1), 0);
  EXPECT_DOUBLE_EQ(pb.agents[0].radius, 0.8);
  EXPECT_TRUE(pb.agents[0].workspace.linear());
  EXPECT_FALSE(pb.body_spec(1).workspace.linear());
  EXPECT_EQ(pb.body_spec(1).name, "rig's cart");
  EXPECT_DOUBLE_EQ(pb.obstacle_clearance(1), 0.2 + 0.8);
  std::vector<std::string> names;
  marsyn::planning::for_each_requirement(pb, [&](const marsyn::planning::Requirement& q) { names.push_back(q.name(pb)); });
  EXPECT_EQ(names, (std::vector<std::string>{"obstacle wall vs rig", "obstacle wall vs rig's cart"}));
  const std::string text = marsyn::summarize(pb);
  EXPECT_NE(text.find("bodies    rig: tractor: radius 0.8, cart: footprint 'cart' radius 0.8"), std::string::npos) << text;
  EXPECT_EQ(pb.agents[0].body, "tractor");
  EXPECT_NE(text.find("constraints per step: 2 (obstacle 2, collision 0"), std::string::npos) << text;
}

TEST(AgentBodies, BadBodiesAreLocatedErrors) {
  std::string e = load_error(edited(kBodies, kBodies + "    workspace: {position: [0, 1]}\n", "both"));
  EXPECT_NE(e.find("give the agent's workspace in its first body of 'bodies', not beside it"), std::string::npos) << e;
  e = load_error(edited("{name: cart, workspace", "{name: tractor, workspace", "twice"));
  EXPECT_NE(e.find("duplicate body name 'tractor' in agent rig"), std::string::npos) << e;
  e = load_error(edited("radius: 0.8}\n    state", "radius: 0.8, size: 2}\n    state", "key"));
  EXPECT_NE(e.find("size"), std::string::npos) << e;
  EXPECT_NE(e.find("agents[0].bodies[1]"), std::string::npos) << e;
  e = load_error(edited(kBodies, "    bodies: {name: tractor}\n", "map"));
  EXPECT_NE(e.find("expected a list of bodies"), std::string::npos) << e;
  e = load_error(edited(kBodies, "    bodies: []\n", "empty"));
  EXPECT_NE(e.find("expected at least one body"), std::string::npos) << e;
  // A body too wide for the bounds is the radius's fault, named with its agent.
  e = load_error(edited("radius: 0.8}\n      - {name: cart", "radius: 7.5}\n      - {name: cart", "wide"));
  EXPECT_NE(e.find("agents[0].bodies[0].radius"), std::string::npos) << e;
  EXPECT_NE(e.find("leave no room for rig's body"), std::string::npos) << e;
  // delta's bounds with a footprint as the first body: located at that body's map.
  e = load_error(edited("delta: {agents: 0.2, obstacles: 0.2}", "delta: {agents: 0.2, obstacles: 0.2, bounds: 0.1}",
                        "bounds"));
  EXPECT_NE(e.find("agents[0].bodies"), std::string::npos) << e;
  e = load_error(edited("{name: tractor, workspace: {position: [0, 1]}", "{name: tractor, workspace: {footprint: cart}",
                        "first_footprint_bounds"));
  EXPECT_EQ(e, "") << e;  // without delta's bounds a footprint first body is fine
  // Bodies in the defaults and an agent's own workspace: which one counts would be a guess.
  std::string moved = slurp(kExample);
  moved.replace(moved.find(kBodies), kBodies.size(), "    workspace: {position: [0, 1]}\n");
  moved.replace(moved.find("agents:\n"), 8,
                "defaults:\n"
                "  bodies:\n"
                "    - {name: tractor, workspace: {position: [0, 1]}, radius: 0.8}\n"
                "    - {name: cart, workspace: {footprint: cart}, radius: 0.8}\n"
                "agents:\n");
  e = load_error(write(moved, "defaults"));
  EXPECT_NE(e.find("the defaults give 'bodies', which would replace this agent's workspace"), std::string::npos) << e;
  e = load_error(edited("{footprint: cart}", "{footprint: trailer}", "unknown"));
  EXPECT_NE(e.find("agents[0].bodies[1].workspace.footprint"), std::string::npos) << e;
}

// The example verifies, and its plan keeps the cart's body (radius 0.8) 0.2 clear of the wall.
// Described by its tractor alone (one point, the same radius), the plan that verifies swings the
// cart's body into the wall on the turn round its end.
TEST(AgentBodies, TheCartIsKeptClearOfAWallTheTractorAloneCuts) {
  const auto lp = marsyn::load_problem(kExample);
  const marsyn::SolveOutcome o = marsyn::solve(lp, marsyn::test::quick_solve());
  ASSERT_TRUE(o.verified) << o.failure;
  const auto [tractor, cart] = closest(o.plan);
  EXPECT_GE(tractor, 0.2 + 0.8 - 1e-9);
  EXPECT_GE(cart, 0.2 + 0.8 - 1e-9);
  const auto alone = marsyn::load_problem(edited(kBodies, "    workspace: {position: [0, 1]}\n    radius: 0.8\n", "alone"));
  const marsyn::SolveOutcome a = marsyn::solve(alone, marsyn::test::quick_solve());
  ASSERT_TRUE(a.verified) << a.failure;
  const auto [t1, c1] = closest(a.plan);
  EXPECT_GE(t1, 0.2 + 0.8 - 1e-9);
  EXPECT_LT(c1, 0.8);  // the cart's body overlaps the wall
}

namespace {

// The side-by-side pair (side_by_side.hpp) whose first agent has a second body, its keel, at
// an offset in y from its point (a linear map with an offset).
marsyn::Problem with_keel(double keel_radius, double keel_offset) {
  marsyn::Problem pb = marsyn::test::side_by_side(0.3, 0.2);
  marsyn::ExtraBody keel;
  keel.agent = 0;
  keel.body = "keel";
  keel.spec = pb.agents[0];
  keel.spec.name = "a's keel";
  keel.spec.workspace.offset = {0.0, keel_offset};
  keel.spec.radius = keel_radius;
  pb.extra_bodies.push_back(keel);
  return pb;
}

}  // namespace

// The keel 0.5 below a's point is 0.35 from the wall: it holds 0.2 + 0.1 and fails 0.2 + 0.2,
// named as the keel; moved up 1.4 (to 0.9) it meets b's point (0.1 + 0.05 + 0.05 away) and the
// pair is named, while a's own point and keel are never a pair.
TEST(AgentBodies, TheCertifierHoldsEveryBodyToItsClearance) {
  const auto ok = marsyn::test::certify_side_by_side(with_keel(0.1, -0.5));
  EXPECT_TRUE(ok.certified) << ok.message;
  EXPECT_NEAR(ok.obstacle.margin, 0.35 - 0.3, 1e-9);
  EXPECT_EQ(ok.obstacle.where, "obstacle wall vs a's keel");
  const auto low = marsyn::test::certify_side_by_side(with_keel(0.2, -0.5));
  EXPECT_FALSE(low.certified);
  EXPECT_NEAR(low.obstacle.margin, -0.05, 1e-9);
  EXPECT_EQ(low.obstacle.where, "obstacle wall vs a's keel");
  const auto up = marsyn::test::certify_side_by_side(with_keel(0.0, 0.9));
  EXPECT_FALSE(up.certified);
  EXPECT_NEAR(up.collision.margin, 0.1 - 0.1 - 0.3, 1e-9);
  EXPECT_EQ(up.collision.where, "collision b vs a's keel");
}
