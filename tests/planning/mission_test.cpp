// Missions on the plan (docs/tasks.md): the schedule of visit knots, the stage constraints in the
// assembly, and the exact check of the stages in order, in their windows, dwelling, and between
// the samples.
#include <gtest/gtest.h>

#include <boost/multiprecision/cpp_bin_float.hpp>

#include <cmath>
#include <vector>
#include <algorithm>
#include <limits>
#include <random>
#include <utility>

#include "dynamics_unicycle/src/unicycle.hpp"
#include "marsyn/core/planning/constraints.hpp"
#include "marsyn/core/planning/mission.hpp"
#include "marsyn/core/planning/robust_check.hpp"

using namespace marsyn;
using namespace marsyn::planning;

namespace {

AgentSpec car(Eigen::Vector3d x0, Eigen::Vector3d goal) {
  AgentSpec a;
  a.name = "car";
  a.dynamics_type = "unicycle";
  a.dynamics = std::make_shared<models::Unicycle>();
  a.x0 = x0;
  a.state_bounds = {Eigen::Vector3d(-10, -10, -4), Eigen::Vector3d(10, 10, 4)};
  a.input_bounds = {Eigen::Vector2d(-20, -100), Eigen::Vector2d(20, 100)};
  a.goal = {goal - Eigen::Vector3d(0.3, 0.3, 3.9), goal + Eigen::Vector3d(0.3, 0.3, 3.9)};
  a.tube.eps = Eigen::Vector3d(0.1, 0.1, 0.1);
  a.tube.w = Eigen::Vector3d::Zero();
  return a;
}

// A square region of half-width h around (x, y) in the workspace.
MissionStage square(const std::string& name, double x, double y, double h) {
  MissionStage s;
  s.name = name;
  s.polygon = {{x - h, y - h}, {x + h, y - h}, {x + h, y + h}, {x - h, y + h}};
  return s;
}

// One car from (0, 0) driving +x at 1 m/s for T = 40 steps of 0.1 s, the goal at (4, 0).
Problem drive(std::vector<MissionStage> stages, Guarantee g = Guarantee::Sampled) {
  Problem p;
  p.agents.push_back(car({0, 0, 0}, {4, 0, 0}));
  p.agents[0].stages = std::move(stages);
  p.tau = 0.1;
  p.horizon = 40;
  p.guarantee = g;
  return p;
}

GlobalPlan at_speed(const std::vector<double>& v) {
  GlobalPlan g;
  for (double s : v) g.u.push_back(Eigen::Vector2d(s, 0));
  return g;
}

const StageVisit& visit(const RobustCheck& r, const std::string& stage) {
  for (const auto& v : r.stages)
    if (v.name == "stage " + stage + " of car") return v;
  throw std::runtime_error("no stage " + stage);
}

}  // namespace

// Knots in proportion to the distance through the regions' centres, each stage after the last.
TEST(Mission, ScheduleFollowsTheDistanceAndTheWindows) {
  Problem p = drive({square("a", 1, 0, 0.3), square("b", 3, 0, 0.3)});
  auto s = schedule_missions(p, 40);
  ASSERT_TRUE(s.feasible) << s.why;
  EXPECT_EQ(s.visit[0], (std::vector<int>{10, 30}));
  // A window moves the knot; a dwell delays the later stages' share of the travel.
  p.agents[0].stages[0].by = 6;
  p.agents[0].stages[1].not_before = 35;
  s = schedule_missions(p, 40);
  ASSERT_TRUE(s.feasible) << s.why;
  EXPECT_EQ(s.visit[0], (std::vector<int>{6, 35}));
  p.agents[0].stages[1].not_before = 1;
  p.agents[0].stages[0].by = -1;
  p.agents[0].stages[0].dwell = 10;
  s = schedule_missions(p, 40);
  EXPECT_EQ(s.visit[0], (std::vector<int>{8, 33}));  // (40 - 10) / 4 = 7.5 -> 8; 10 + 8 + 15 = 33
  // A later stage's window pulls the earlier ones forward: b by 12 puts a (dwelling 10) at 1.
  p.agents[0].stages[1].by = 12;
  s = schedule_missions(p, 40);
  ASSERT_TRUE(s.feasible) << s.why;
  EXPECT_EQ(s.visit[0], (std::vector<int>{1, 12}));
  // A window that the order cannot meet.
  p.agents[0].stages[1].by = 11;
  s = schedule_missions(p, 40);
  EXPECT_FALSE(s.feasible);
  EXPECT_NE(s.why.find("stage 'a' of car cannot be visited"), std::string::npos) << s.why;
}

// The stage's constraint: rows only at its knots, the region shrunk by eps.
TEST(Mission, AssemblyAddsTheStageAtItsKnotsOnly) {
  Problem p = drive({square("a", 1, 0, 0.3)});
  p.agents[0].stages[0].dwell = 2;
  const PlanningProblem pp = assemble(p, 40, {});
  const Constraint* c = nullptr;
  for (const auto& q : pp.constraints)
    if (q->name() == "stage a of car") c = q.get();
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->stage(), ConstraintStage::AtSteps);
  EXPECT_EQ(c->steps(), (std::vector<int>{10, 11, 12}));  // a quarter of the 38 steps of travel: 9.5 -> 10
  EXPECT_TRUE(applies_at(*c, 11, 40));
  EXPECT_FALSE(applies_at(*c, 9, 40));
  EXPECT_FALSE(applies_at(*c, 13, 40));
  // At x = (1, 0) every row holds with margin 0.3 - eps - buffer; at (1.25, 0) the +x edge fails.
  std::vector<double> g(c->size()), x{1.0, 0.0, 0.0};
  c->evaluate(x.data(), g.data(), nullptr);
  for (double v : g) EXPECT_LE(v, -(0.3 - 0.1 - 1e-3) + 1e-12);
  x[0] = 1.25;
  c->evaluate(x.data(), g.data(), nullptr);
  EXPECT_GT(*std::max_element(g.begin(), g.end()), 0.0);
  ASSERT_FALSE(pp.waypoints.empty());
  EXPECT_DOUBLE_EQ(pp.waypoints.front().x[0], 1.0);
  EXPECT_TRUE(std::isnan(pp.waypoints.front().x[2]));
}

// The order of the stages: a straight drive meets a (x = 1) before b (x = 3); the mission b
// then a asks for b at the earlier knot and fails.
TEST(Mission, TheCheckHoldsThePlanToTheOrder) {
  const GlobalPlan plan = at_speed(std::vector<double>(40, 1.0));
  const auto ok = check_robust(drive({square("a", 1, 0, 0.3), square("b", 3, 0, 0.3)}), plan);
  EXPECT_TRUE(ok.passed) << ok.message;
  ASSERT_EQ(ok.stages.size(), 2u);
  EXPECT_EQ(visit(ok, "a").step, 10);
  EXPECT_NEAR(visit(ok, "a").margin, 0.2, 1e-9);
  const auto bad = check_robust(drive({square("b", 3, 0, 0.3), square("a", 1, 0, 0.3)}), plan);
  EXPECT_FALSE(bad.passed);
  EXPECT_LT(visit(bad, "b").margin, 0);
  EXPECT_NE(bad.message.find("stage"), std::string::npos) << bad.message;
}

// A window: `by: 6` asks for region a (x = 1) at knot 6, where the car is at 0.6.
TEST(Mission, WindowsAreEnforced) {
  const GlobalPlan plan = at_speed(std::vector<double>(40, 1.0));
  Problem p = drive({square("a", 1, 0, 0.3)});
  p.agents[0].stages[0].by = 6;
  const auto bad = check_robust(p, plan);
  EXPECT_FALSE(bad.passed);
  EXPECT_EQ(visit(bad, "a").step, 6);
  EXPECT_NEAR(visit(bad, "a").margin, -0.2, 1e-9);  // 0.6 - 0.1 vs the edge at 0.7
  // Driving faster first reaches it in time.
  std::vector<double> v(40, 3.0 / 3.4);
  for (int k = 0; k < 6; ++k) v[k] = 10.0 / 6.0;
  const auto ok = check_robust(p, at_speed(v));
  EXPECT_TRUE(ok.passed) << ok.message;
}

// A dwell: the car must stay in a for 5 knots; passing through at 1 m/s leaves it after 2.
TEST(Mission, ADwellKeepsTheAgentInside) {
  Problem p = drive({square("a", 1, 0, 0.3)});
  p.agents[0].stages[0].dwell = 5;
  const auto s = schedule_missions(p, 40);
  const int k0 = s.visit[0][0];
  const auto bad = check_robust(p, at_speed(std::vector<double>(40, 1.0)));
  EXPECT_FALSE(bad.passed);
  std::vector<double> v(40, 0.0);
  for (int k = 0; k < k0; ++k) v[k] = 1.0 / (k0 * 0.1);  // reach x = 1 at the visit knot
  for (int k = k0 + 5; k < 40; ++k) v[k] = 3.0 / ((40 - k0 - 5) * 0.1);
  const auto ok = check_robust(p, at_speed(v));
  EXPECT_TRUE(ok.passed) << ok.message;
  EXPECT_EQ(visit(ok, "a").dwell, 5);
}

// A stage's knot can make one leg much faster than the whole path's average (a team stage: a
// robot waits for the others, then crosses the room). The clearance between the samples is sized
// by the fastest leg: the car covers 1 m to the stage by knot 10, dwells until knot 25, then 3 m
// in 15 knots (2 m/s against the path's 1 m/s).
TEST(Mission, ClearanceBetweenTheSamplesFollowsTheFastestLeg) {
  // The car with stage a at a fixed knot and dwell: the problem and its schedule at T = 40.
  auto visit_at = [](int knot, int dwell) {
    MissionStage st = square("a", 1, 0, 0.2);
    st.not_before = st.by = knot;
    st.dwell = dwell;
    Problem p = drive({st}, Guarantee::Continuous);
    MissionSchedule sched = schedule_missions(p, 40);
    EXPECT_EQ(sched.visit[0][0], knot);
    return std::make_pair(p, sched);
  };
  const AssemblyOptions o;  // the midpoint, clearance 1: tau / 2 x (twice the speed)
  const auto [p, sched] = visit_at(10, 15);
  EXPECT_NEAR(fastest_leg_speed(p.agents[0], sched.visit[0], 40, 0.1), 2.0, 1e-12);
  EXPECT_NEAR(between_clearance(p, 0, sched, 40, o), 0.05 * 2 * 2.0, 1e-12);
  // Without stages: twice the path's average, as before.
  const Problem plain = drive({}, Guarantee::Continuous);
  EXPECT_EQ(fastest_leg_speed(plain.agents[0], {}, 40, 0.1), 0.0);
  EXPECT_NEAR(between_clearance(plain, 0, schedule_missions(plain, 40), 40, o), 0.05 * 2 * 1.0, 1e-12);
  // Capped by the field's bound (20 m/s here): legs of one knot (10 and 30 m/s) ask no more.
  const auto [rush, fast] = visit_at(1, 38);
  EXPECT_NEAR(fastest_leg_speed(rush.agents[0], fast.visit[0], 40, 0.1), 30.0, 1e-9);
  EXPECT_NEAR(between_clearance(rush, 0, fast, 40, o), 0.05 * 20.0, 1e-12);
}

// Between the samples: a loop within one period returns to the same point, so every knot of the
// dwell is deep inside, but the continuous nominal leaves the region in between. The sampled
// guarantee passes it; the continuous one names the stage between the samples.
TEST(Mission, ContinuousTimeSeesTheFlowLeaveADwellRegion) {
  Problem p = drive({square("a", 1, 0, 0.25)});
  p.agents[0].stages[0].dwell = 1;
  // The loop turns the heading by 2 pi: bounds and goal that allow it.
  p.agents[0].state_bounds.lo[2] = -11;
  p.agents[0].state_bounds.hi[2] = 11;
  p.agents[0].goal.lo[2] = -10;
  p.agents[0].goal.hi[2] = 10;
  const int k0 = schedule_missions(p, 40).visit[0][0];
  std::vector<Eigen::VectorXd> u(40, Eigen::Vector2d(0, 0));
  for (int k = 0; k < k0; ++k) u[k] = Eigen::Vector2d(1.0 / (k0 * 0.1), 0);
  // One full turn in tau = 0.1 s at 10 m/s: a circle of radius 10 / (2 pi / 0.1) = 0.16 m.
  u[k0] = Eigen::Vector2d(10.0, 2 * M_PI / 0.1);
  for (int k = k0 + 1; k < 40; ++k) u[k] = Eigen::Vector2d(3.0 / ((40 - k0 - 1) * 0.1), 0);
  GlobalPlan plan;
  plan.u = u;
  const auto sampled = check_robust(p, plan);
  EXPECT_TRUE(sampled.passed) << sampled.message;
  p.guarantee = Guarantee::Continuous;
  const auto cont = check_robust(p, plan);
  EXPECT_FALSE(cont.passed);
  EXPECT_GE(visit(cont, "a").sampled_margin, 0.0);
  EXPECT_LT(visit(cont, "a").between_margin, 0.0);
  EXPECT_TRUE(cont.between_shortfalls.count("stage a of car")) << cont.message;
}

// Sound margins on boxes: a box region measures the state box, a polygon the workspace box.
TEST(Mission, StageMarginOnBoxes) {
  MissionStage s = square("a", 0, 0, 1);
  const Box ws{Eigen::Vector2d(0.5, -0.2), Eigen::Vector2d(0.7, 0.9)};
  EXPECT_NEAR(stage_margin(s, ws, ws), 0.1, 1e-12);
  const Box out{Eigen::Vector2d(0.5, -0.2), Eigen::Vector2d(1.2, 0.3)};
  EXPECT_NEAR(stage_margin(s, out, out), -0.2, 1e-12);
  MissionStage b;
  b.box = {Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(1, 1, 1)};
  const Box st{Eigen::Vector3d(0.2, 0.3, -0.5), Eigen::Vector3d(0.4, 0.95, 0.5)};
  EXPECT_NEAR(stage_margin(b, st, ws), 0.05, 1e-12);
}

// stage_margin's bounds by directed rounding in round-to-nearest: never above the exact margin
// (computed here to 100 digits), and within a few units in the last place of it. (Boost.Interval
// on point intervals, as it was written before, came out above the exact value: GCC computes
// both ends of one such expression once, in the mode it set first.) Random convex polygons and
// boxes; box regions to the last bit (one subtraction rounded down).
TEST(Mission, StageMarginIsALowerBoundOfTheExactMargin) {
  using Big = boost::multiprecision::cpp_bin_float_100;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3.0, 3.0), r(0.3, 2.0), w(0.0, 0.8);
  for (int trial = 0; trial < 500; ++trial) {
    MissionStage s;
    s.name = "p";
    const int V = 3 + trial % 5;
    const Eigen::Vector2d c(u(rng), u(rng));
    std::vector<double> ang;
    for (int i = 0; i < V; ++i) ang.push_back(std::uniform_real_distribution<double>(0, 2 * M_PI)(rng));
    std::sort(ang.begin(), ang.end());
    const double rad = r(rng);
    for (double a : ang) s.polygon.push_back(c + rad * Eigen::Vector2d(std::cos(a), std::sin(a)));
    const Eigen::Vector2d lo(c.x() + u(rng) / 3, c.y() + u(rng) / 3);
    const Box ws{lo, lo + Eigen::Vector2d(w(rng), w(rng))};
    // Exact: the smallest over corners and edges of cross(e, p - v) / |e|.
    Big exact = 1e300;
    for (double x : {ws.lo[0], ws.hi[0]})
      for (double y : {ws.lo[1], ws.hi[1]})
        for (int i = 0; i < V; ++i) {
          const auto& v = s.polygon[i];
          const auto& q = s.polygon[(i + 1) % V];
          const Big ex = Big(q.x()) - Big(v.x()), ey = Big(q.y()) - Big(v.y());
          const Big d = (ex * (Big(y) - Big(v.y())) - ey * (Big(x) - Big(v.x()))) / sqrt(ex * ex + ey * ey);
          if (d < exact) exact = d;
        }
    const double m = stage_margin(s, ws, ws);
    ASSERT_LE(Big(m), exact) << trial;
    ASSERT_GE(Big(m), exact - Big(1e-13) * (1 + abs(exact))) << trial;
  }
  MissionStage b;
  b.box = {Eigen::Vector3d(0.1, -0.3, -1), Eigen::Vector3d(1.7, 1.1, 1)};
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d lo(u(rng), u(rng), u(rng));
    const Box st{lo, lo + Eigen::Vector3d(w(rng), w(rng), w(rng))};
    Big exact = 1e300;
    for (int k = 0; k < 3; ++k) {
      const Big a = Big(st.lo[k]) - Big(b.box.lo[k]), z = Big(b.box.hi[k]) - Big(st.hi[k]);
      if (a < exact) exact = a;
      if (z < exact) exact = z;
    }
    const double m = stage_margin(b, st, st);
    ASSERT_LE(Big(m), exact) << trial;
    ASSERT_GT(Big(std::nextafter(m, 1e300)), exact) << trial;  // the largest double not above it
  }
}

// Re-timing (docs/tasks.md, "What is planned"): the car at 0.5 m/s passes deepest through a
// (x = 1) at knot 20, half of its path, so the re-timed knot is 20 (the initial schedule's is 10);
// a window clamps it, and a knot the user fixed (not_before == by) does not move.
TEST(Mission, RetimingMovesTheKnotsTheWindowsLeaveFree) {
  Problem p = drive({square("a", 1, 0, 0.3)});
  const auto x = rollout(p, at_speed(std::vector<double>(40, 0.5)).u);
  const MissionSchedule initial = schedule_missions(p, 40);
  ASSERT_EQ(initial.visit[0][0], 10);
  MissionSchedule r = retime_missions(p, initial, x);
  ASSERT_TRUE(r.feasible) << r.why;
  EXPECT_EQ(r.horizon, 40);
  EXPECT_EQ(r.visit[0][0], 20);
  p.agents[0].stages[0].by = 15;
  EXPECT_EQ(retime_missions(p, initial, x).visit[0][0], 15);
  p.agents[0].stages[0].not_before = p.agents[0].stages[0].by = 10;
  EXPECT_EQ(retime_missions(p, initial, x).visit[0][0], 10);
}

// A team stage: two cars pass their seats at different knots (20 and 10); re-timed, both meet at
// one knot, the later one.
TEST(Mission, RetimedTeamStagesShareOneKnot) {
  Problem p = drive({square("a", 1, 0, 0.3)});
  p.agents.push_back(car({0, 2, 0}, {4, 2, 0}));
  p.agents[1].name = "other";
  p.agents[1].stages = {square("b", 1, 2, 0.3)};
  p.agents[0].stages[0].team = p.agents[1].stages[0].team = "meet";
  GlobalPlan plan;
  for (int k = 0; k < 40; ++k) plan.u.push_back((Eigen::VectorXd(4) << 0.5, 0, 1.0, 0).finished());
  const MissionSchedule r = retime_missions(p, schedule_missions(p, 40), rollout(p, plan.u));
  ASSERT_TRUE(r.feasible) << r.why;
  EXPECT_EQ(r.visit[0][0], 20);
  EXPECT_EQ(r.visit[1][0], 20);
  EXPECT_EQ(schedule_error(p, r, 40), "");
}

// The exact check judges the stages at the knots it is given (the plan's): the car at 0.5 m/s is
// in a at knot 20, not at the initial schedule's 10; knots outside a window fail by name.
TEST(Mission, TheCheckJudgesTheStagesAtThePlansKnots) {
  Problem p = drive({square("a", 1, 0, 0.3)});
  const GlobalPlan plan = at_speed(std::vector<double>(40, 0.5));
  const MissionSchedule at20{{{20}}, 40};
  const auto initial = check_robust(p, plan);
  EXPECT_EQ(visit(initial, "a").step, 10);
  EXPECT_LT(visit(initial, "a").margin, 0);
  const auto chosen = check_robust(p, plan, at20);
  EXPECT_EQ(visit(chosen, "a").step, 20);
  EXPECT_NEAR(visit(chosen, "a").margin, 0.2, 1e-9);
  p.agents[0].stages[0].by = 15;
  const auto late = check_robust(p, plan, at20);
  EXPECT_FALSE(late.passed);
  EXPECT_NE(late.message.find("mission schedule: stage 'a' of car: knot 20 is after by 15"), std::string::npos)
      << late.message;
}

// with_visits: the problem whose windows are the knots, so that the initial schedule of it is
// the plan's (what the certifier and the verification runs are given); the original keeps its
// windows, and knots that are no schedule leave the problem as it is.
TEST(Mission, WithVisitsFixesEveryWindowAtItsKnot) {
  const Problem p = drive({square("a", 1, 0, 0.3), square("b", 3, 0, 0.3)});
  const MissionSchedule s{{{17, 25}}, 40};
  const Problem fixed = with_visits(p, s);
  EXPECT_EQ(schedule_missions(fixed, 40).visit, s.visit);
  EXPECT_EQ(fixed.agents[0].stages[1].not_before, 25);
  EXPECT_EQ(fixed.agents[0].stages[1].by, 25);
  EXPECT_EQ(p.agents[0].stages[1].by, -1);
  const MissionSchedule disordered{{{25, 17}}, 40};
  EXPECT_NE(schedule_error(p, disordered, 40), "");
  EXPECT_EQ(schedule_missions(with_visits(p, disordered), 40).visit, schedule_missions(p, 40).visit);
}
