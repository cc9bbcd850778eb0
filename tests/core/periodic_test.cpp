// Periodic coordinates (issue 54 item 3, docs/problem-format.md "Periodic coordinates"): a
// heading left free with `any`, a goal written on the circle kept on the branch of the lift
// nearest the start (the shorter way round, inside the bounds), `any` where it is not allowed,
// an angle's tube below a quarter turn, and a left turn through +-pi that plans and verifies.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/solve.hpp"
#include "marsyn/periodic.hpp"
#include "load_error.hpp"
#include "problem_variant.hpp"
#include "quick_solve.hpp"

namespace {

using marsyn::test::load_error;
constexpr double kPi = 3.141592653589793;

std::string base_file() { return std::string(MARSYN_SOURCE_DIR) + "/tests/problems/periodic/left_turn_wrap.yaml"; }

std::string variant(const std::vector<std::pair<std::string, std::string>>& edits, const std::string& tag) {
  return marsyn::test::problem_variant(base_file(), edits, "periodic_" + tag);
}

TEST(Periodic, AnyBoundsTurnFreelyAndTheGoalTakesTheShorterWayRound) {
  const marsyn::LoadedProblem lp = marsyn::load_problem(base_file());
  const auto& west = lp.problem.agents[0];
  EXPECT_NEAR(west.state_bounds.lo[2], 3.14159 - 4 * kPi, 1e-12);
  EXPECT_NEAR(west.state_bounds.hi[2], 3.14159 + 4 * kPi, 1e-12);
  // Written -pi/2 +- 0.4 (south); kept at 3 pi/2 +- 0.4: a quarter turn left from pi.
  EXPECT_NEAR(west.goal.center()[2], -1.5708 + 2 * kPi, 1e-12);
  EXPECT_NEAR(west.goal.hi[2] - west.goal.lo[2], 0.8, 1e-12);
  // Already the nearest branch: unchanged.
  EXPECT_DOUBLE_EQ(lp.problem.agents[1].goal.center()[2], 1.5708);
  // Coordinates that are not periodic keep what the file says.
  EXPECT_DOUBLE_EQ(west.state_bounds.hi[0], 12);
  EXPECT_DOUBLE_EQ(west.goal.lo[0], 5.9);
}

TEST(Periodic, BoundsWrittenAsNumbersBoundTheLift) {
  // Bounds [-4, 4] stop the left turn's branch (4.71): the goal keeps the one inside them.
  const marsyn::LoadedProblem lp =
      marsyn::load_problem(variant({{"lo: [0, 0, any], hi: [12, 10, any]", "lo: [0, 0, -4], hi: [12, 10, 4]"}}, "numbers"));
  const auto& west = lp.problem.agents[0];
  EXPECT_DOUBLE_EQ(west.state_bounds.lo[2], -4);
  EXPECT_NEAR(west.goal.center()[2], -1.5708, 1e-12);
  // An arc of bounds narrower than a turn is moved to the branch that holds x0.
  const marsyn::LoadedProblem arc =
      marsyn::load_problem(variant({{"lo: [0, 0, any], hi: [12, 10, any]", "lo: [0, 0, -7], hi: [12, 10, -1]"},
                                    {"goal: {center: [6.4, 1, -1.5708]", "goal: {center: [6.4, 1, 4]"}},
                                   "arc"));
  EXPECT_NEAR(arc.problem.agents[0].state_bounds.lo[2], -7 + 2 * kPi, 1e-12);
  EXPECT_NEAR(arc.problem.agents[0].state_bounds.hi[2], -1 + 2 * kPi, 1e-12);
  EXPECT_DOUBLE_EQ(arc.problem.agents[0].goal.center()[2], 4);
}

TEST(Periodic, AnyGoalSpansTheBoundsAndItsTubeATwentiethOfATurn) {
  const marsyn::LoadedProblem lp = marsyn::load_problem(variant(
      {{"radius: [0.5, 0.6, 0.4]}", "radius: [0.5, 0.6, any]}"}, {"  eps: [0.15, 0.15, 0.2]\n", ""},
       {"  eta_x: [0.025, 0.025, 0.03]\n", ""}, {"  eta_u: [0.25, 0.25]\n", ""}},
      "any_goal"));
  const auto& west = lp.problem.agents[0];
  EXPECT_DOUBLE_EQ(west.goal.lo[2], west.state_bounds.lo[2]);
  EXPECT_DOUBLE_EQ(west.goal.hi[2], west.state_bounds.hi[2]);
  // 5 % of one turn, not of the four turns the free bounds allow.
  EXPECT_NEAR(west.tube.eps[2], 0.05 * 2 * kPi, 1e-12);
}

// A patrol round an island back to the start heading: the heading winds a turn on (anticlockwise)
// or back (clockwise), not the unwound branch nearest x0, which made each boat spin in place.
TEST(Periodic, APatrolKeepsItsGoalOnTheBranchItsWayWindsTo) {
  const std::string path = std::string(MARSYN_SOURCE_DIR) + "/tests/problems/periodic/patrol_island.yaml";
  const marsyn::LoadedProblem lp = marsyn::load_problem(path);
  EXPECT_NEAR(lp.problem.agents[0].goal.center()[2], 2 * kPi, 1e-9);
  EXPECT_NEAR(lp.problem.agents[1].goal.center()[2], 3.14159 - 2 * kPi, 1e-9);
  const marsyn::SolveOutcome o = marsyn::solve(lp, marsyn::test::quick_solve());
  EXPECT_TRUE(o.verified) << o.failure;
}

// The same boat written in coordinates 20 m north of the island's frame (a workspace offset):
// its way is followed in the workspace, where the island and the check-points are, so it winds
// the same turn. Read in its own coordinates the start lay north of the check-points and the
// goal went a turn the other way.
TEST(Periodic, AWorkspaceOffsetWindsTheWayWhereTheObstaclesAre) {
  const std::string patrol = std::string(MARSYN_SOURCE_DIR) + "/tests/problems/periodic/patrol_island.yaml";
  const marsyn::LoadedProblem lp = marsyn::load_problem(marsyn::test::problem_variant(
      patrol,
      {{"    x0: [-1.0, -5.0, 0]\n    goal: {center: [-1.0, -5.0, 0], radius: [0.5, 0.5, 0.4]}\n",
        "    x0: [-1.0, 15.0, 0]\n    goal: {center: [-1.0, 15.0, 0], radius: [0.5, 0.5, 0.4]}\n"
        "    state_bounds: {lo: [-8, 12, any], hi: [8, 28, any]}\n"
        "    workspace: {position: [x, y], offset: [0, -20]}\n"}},
      "periodic_patrol_offset"));
  EXPECT_NEAR(lp.problem.agents[0].goal.center()[2], 2 * kPi, 1e-9);
  EXPECT_NEAR(lp.problem.agents[1].goal.center()[2], 3.14159 - 2 * kPi, 1e-9);
}

TEST(Periodic, AStageRegionReadsAnyAndArcsAsTheGoalDoes) {
  const marsyn::LoadedProblem lp = marsyn::load_problem(variant(
      {{"    goal: {center: [6.4, 1, -1.5708], radius: [0.5, 0.6, 0.4]}\n",
        "    goal: {center: [6.4, 1, -1.5708], radius: [0.5, 0.6, 0.4]}\n"
        "    stages:\n"
        "      - {name: junction, region: {center: [6, 5, any], radius: [0.8, 0.8, any]}}\n"
        "      - {name: turning, region: {center: [6, 3, -2.4], radius: [1, 1, 0.9]}}\n"}},
      "stages"));
  const auto& st = lp.problem.agents[0].stages;
  ASSERT_EQ(st.size(), 2u);
  EXPECT_DOUBLE_EQ(st[0].box.lo[2], lp.problem.agents[0].state_bounds.lo[2]);
  EXPECT_DOUBLE_EQ(st[0].box.hi[2], lp.problem.agents[0].state_bounds.hi[2]);
  EXPECT_NEAR(st[1].box.lo[2], -2.4 - 0.9 + 2 * kPi, 1e-12);  // written -2.4, kept at 3.88 (nearer pi)
}

TEST(Periodic, AnyWhereItIsNotAllowedAndWideAngleTubesAreLocatedErrors) {
  const std::string x_any = load_error(variant({{"lo: [0, 0, any], hi: [12, 10, any]", "lo: [any, 0, any], hi: [any, 10, any]"}}, "x_any"));
  EXPECT_NE(x_any.find("state_bounds.lo[0]"), std::string::npos) << x_any;
  EXPECT_NE(x_any.find("only in the bounds of a periodic coordinate (the dynamics 'unicycle' turns freely in theta)"), std::string::npos) << x_any;
  const std::string one_side = load_error(variant({{"hi: [12, 10, any]", "hi: [12, 10, 4]"}}, "one_side"));
  EXPECT_NE(one_side.find("'any' on one side only"), std::string::npos) << one_side;
  const std::string wide = load_error(variant({{"eps: [0.15, 0.15, 0.2]", "eps: [0.15, 0.15, 1.6]"}}, "wide"));
  EXPECT_NE(wide.find("eps[2]"), std::string::npos) << wide;
  EXPECT_NE(wide.find("below pi/2"), std::string::npos) << wide;
  // A model with no periodic coordinate says so.
  const std::string none = load_error(variant({{"  dynamics: unicycle\n", "  dynamics: unicycle\n"},
                                               {"    x0: [11, 5.4, 3.14159]\n", "    x0: [11, 5.4, 3.14159]\n    dynamics: {states: [x, y, th], inputs: [v, w], field: {x: v * cos(th), y: v * sin(th), th: w}}\n"}},
                                              "none"));
  EXPECT_NE(none.find("these equations declare none"), std::string::npos) << none;
}

TEST(Periodic, EquationsDeclareTheirAnglesAndAreCheckedForIt) {
  const std::string eq = "    dynamics: {states: [x, y, th], inputs: [v, w], periodic: [th], field: {x: v * cos(th), y: v * sin(2 * th - pi), th: w}}\n";
  const marsyn::LoadedProblem lp =
      marsyn::load_problem(variant({{"    x0: [11, 5.4, 3.14159]\n", "    x0: [11, 5.4, 3.14159]\n" + eq}}, "eq"));
  EXPECT_EQ(lp.problem.agents[0].dynamics->periodic(), (std::vector<bool>{false, false, true}));
  EXPECT_NEAR(lp.problem.agents[0].goal.center()[2], -1.5708 + 2 * kPi, 1e-12);
  const std::string drift = "    dynamics: {states: [x, y, th], inputs: [v, w], periodic: [th], field: {x: v * cos(th), y: v * sin(th), th: w - 0.1 * th}}\n";
  const std::string e1 = load_error(variant({{"    x0: [11, 5.4, 3.14159]\n", "    x0: [11, 5.4, 3.14159]\n" + drift}}, "drift"));
  EXPECT_NE(e1.find("the equation of 'th' is not 2 pi-periodic in 'th'"), std::string::npos) << e1;
  const std::string half = "    dynamics: {states: [x, y, th], inputs: [v, w], periodic: [th], field: {x: v * cos(0.5 * th), y: v * sin(th), th: w}}\n";
  const std::string e2 = load_error(variant({{"    x0: [11, 5.4, 3.14159]\n", "    x0: [11, 5.4, 3.14159]\n" + half}}, "half"));
  EXPECT_NE(e2.find("the equation of 'x' is not 2 pi-periodic"), std::string::npos) << e2;
  const std::string typo = "    dynamics: {states: [x, y, th], inputs: [v, w], periodic: [theta], field: {x: v * cos(th), y: v * sin(th), th: w}}\n";
  const std::string e3 = load_error(variant({{"    x0: [11, 5.4, 3.14159]\n", "    x0: [11, 5.4, 3.14159]\n" + typo}}, "typo"));
  EXPECT_NE(e3.find("periodic[0]"), std::string::npos) << e3;
  EXPECT_NE(e3.find("'theta' is not a state"), std::string::npos) << e3;
}

TEST(Periodic, ALeftTurnThroughPiPlansAndVerifies) {
  const marsyn::LoadedProblem lp = marsyn::load_problem(base_file());
  const marsyn::SolveOutcome o = marsyn::solve(lp, marsyn::test::quick_solve());
  ASSERT_TRUE(o.verified) << o.failure;
  // The westbound car turned a quarter left (pi -> 3 pi / 2) and never the long way round.
  const auto& x = o.plan.nominal[0].x;
  EXPECT_NEAR(x.back()[2], 1.5 * kPi, 0.4);
  for (const auto& s : x) EXPECT_GT(s[2], 0.5 * kPi);
}

}  // namespace

namespace {

// The closed loop of a unicycle under an adversary that pushes every coordinate away from the
// nominal at full W. The controller reads the heading as a compass reports it, in (-pi, pi]
// (compass), or the lifted truth. Returns the step at which the controller refused the state or
// the robot left its tube (on the circle), T when it kept the tube to the end.
int wrapped_closed_loop(const marsyn::Controller& c, const marsyn::AgentSpec& a, const marsyn::NominalTrajectory& nom, double tau,
                        bool compass, double* worst_tube_use) {
  const int T = static_cast<int>(nom.u.size());
  Eigen::Vector3d x = nom.x[0];  // the lifted truth
  *worst_tube_use = 0;
  for (int k = 0; k < T; ++k) {
    Eigen::Vector3d read = x;
    if (compass) read[2] = std::remainder(x[2], marsyn::kTurn);
    double u[2];
    if (c.input(read.data(), k, u) != marsyn::ControlStatus::Ok) return k;
    // The adversary: away from the nominal of the next sample in every coordinate.
    const Eigen::VectorXd& next = nom.x[static_cast<std::size_t>(k + 1)];
    const int sub = 20;
    const double h = tau / sub;
    for (int s = 0; s < sub; ++s) {
      auto f = [&](const Eigen::Vector3d& z) {
        Eigen::Vector3d d(u[0] * std::cos(z[2]), u[0] * std::sin(z[2]), u[1]);
        for (int i = 0; i < 3; ++i) d[i] += (z[i] >= next[i] ? 1.0 : -1.0) * a.tube.w[i];
        return d;
      };
      const Eigen::Vector3d k1 = f(x), k2 = f(x + 0.5 * h * k1), k3 = f(x + 0.5 * h * k2), k4 = f(x + h * k3);
      x += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    for (int i = 0; i < 3; ++i) {
      const double off = i == 2 ? std::abs(marsyn::angle_difference(x[i], next[i])) : std::abs(x[i] - next[i]);
      *worst_tube_use = std::max(*worst_tube_use, off / a.tube.eps[i]);
      if (off > a.tube.eps[i]) return k + 1;
    }
  }
  return T;
}

void expect_kept_across_the_wrap(const std::string& path, const std::string& tracker) {
  const marsyn::LoadedProblem lp = marsyn::load_problem(path);
  const marsyn::SolveOutcome o = marsyn::solve(lp, marsyn::test::quick_solve());
  ASSERT_TRUE(o.verified) << o.failure;
  const auto& a = o.problem.agents[0];
  const auto& nom = o.plan.nominal[0];
  ASSERT_EQ(o.agents[0].tracker, tracker);
  const int T = static_cast<int>(nom.u.size());
  // The heading crosses pi: the compass's reading jumps by a turn while the truth does not.
  int crossing = -1;
  for (int k = 0; k <= T; ++k)
    if (nom.x[static_cast<std::size_t>(k)][2] > M_PI && crossing < 0) crossing = k;
  ASSERT_GT(crossing, 0);
  ASSERT_LT(crossing, T);
  // The controller lifts the compass's reading itself (onto its step's reference): the same
  // run as on the lifted truth. A controller that ignored the wrap would refuse the state at the
  // crossing (checked once by removing the lift from both controllers: both refused at step 1,
  // where the heading first passes pi).
  double use = 0, use_truth = 0;
  EXPECT_EQ(wrapped_closed_loop(*o.agents[0].track.controller, a, nom, o.problem.tau, true, &use), T) << tracker;
  EXPECT_EQ(wrapped_closed_loop(*o.agents[0].track.controller, a, nom, o.problem.tau, false, &use_truth), T) << tracker;
  EXPECT_LE(use, 1.0);
  EXPECT_NEAR(use, use_truth, 1e-9);
  EXPECT_GT(use, 0.05);  // the adversary did push
}

TEST(Periodic, TheFunnelKeepsItsTubeAcrossTheWrapUnderTheAdversary) {
  expect_kept_across_the_wrap(base_file(), "funnel");
}

TEST(Periodic, TheAbstractionKeepsItsTubeAcrossTheWrapUnderTheAdversary) {
  expect_kept_across_the_wrap(variant({{"horizon: 90\n", "horizon: 90\ntracker: abcd\n"}}, "abcd"), "abcd");
}

}  // namespace
