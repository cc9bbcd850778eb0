#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "dynamics_quadrotor/src/quadrotor.hpp"
#include "dynamics_unicycle/src/unicycle.hpp"
#include "marsyn/core/planning/box_margins.hpp"
#include "marsyn/core/planning/constraints.hpp"
#include "marsyn/core/planning/projector.hpp"
#include "marsyn/core/planning/robust_check.hpp"
#include "marsyn/core/planning/spec_margins.hpp"
#include "marsyn/sampled_map.hpp"

using namespace marsyn;
using namespace marsyn::planning;

namespace {

AgentSpec unicycle(const std::string& name, Eigen::Vector3d x0) {
  AgentSpec a;
  a.name = name;
  a.dynamics_type = "unicycle";
  a.dynamics = std::make_shared<models::Unicycle>();
  a.x0 = x0;
  a.state_bounds = {Eigen::Vector3d(-10, -10, -4), Eigen::Vector3d(10, 10, 4)};
  a.input_bounds = {Eigen::Vector2d(-2, -2), Eigen::Vector2d(2, 2)};
  a.goal = {Eigen::Vector3d(-10, -10, -4), Eigen::Vector3d(10, 10, 4)};
  a.tube.eps = Eigen::Vector3d(0.1, 0.1, 0.1);
  a.tube.w = Eigen::Vector3d::Zero();
  return a;
}

// One unicycle driving +x at speed 1 for 1 s (ends at x = 1) towards a box whose near face is at
// `face`: with delta = 0.2 (inf-norm) and eps = 0.1 the robust spec needs 1 <= face - 0.3.
Problem drive_to_wall(double face) {
  Problem p;
  p.agents.push_back(unicycle("car", {0, 0, 0}));
  Obstacle o;
  o.name = "wall";
  o.vertices = {{face, -1}, {face + 1, -1}, {face + 1, 1}, {face, 1}};
  p.obstacles.push_back(o);
  p.delta = 0.2;
  p.delta_norm = Norm::Inf;
  p.tau = 0.1;
  p.horizon = 10;
  return p;
}

GlobalPlan straight(int T, int agents) {
  GlobalPlan g;
  for (int k = 0; k < T; ++k) {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(2 * agents);
    for (int i = 0; i < agents; ++i) u[2 * i] = 1.0;
    g.u.push_back(u);
  }
  return g;
}

}  // namespace

// At the samples (the paper's semantics): the step where the margin is smallest.
TEST(RobustCheck, AcceptsAClearMarginAndRejectsASlightViolation) {
  Problem clear = drive_to_wall(1.3 + 1e-3), close = drive_to_wall(1.3 - 1e-3);
  clear.guarantee = close.guarantee = Guarantee::Sampled;
  const auto ok = check_robust(clear, straight(10, 1));
  EXPECT_TRUE(ok.passed) << ok.message;
  EXPECT_NEAR(ok.min_margin, 1e-3, 1e-6);
  const auto bad = check_robust(close, straight(10, 1));
  EXPECT_FALSE(bad.passed);
  EXPECT_NEAR(bad.min_margin, -1e-3, 1e-6);
  EXPECT_EQ(bad.worst, "obstacle wall vs car");
  EXPECT_EQ(bad.worst_step, 10);
  EXPECT_FALSE(bad.continuous);
}

// Continuous time (the default): driving straight at the wall, the motion between the samples
// adds nothing to the last sample's margin (up to the flow enclosure's rounding), and the
// violation is named by its period.
TEST(RobustCheck, ContinuousTimeAlongAStraightApproach) {
  const auto ok = check_robust(drive_to_wall(1.3 + 1e-3), straight(10, 1));
  EXPECT_TRUE(ok.passed) << ok.message;
  EXPECT_TRUE(ok.continuous);
  EXPECT_NEAR(ok.min_margin, 1e-3, 1e-6);
  EXPECT_NEAR(ok.between_margin, 1e-3, 1e-6);
  const auto bad = check_robust(drive_to_wall(1.3 - 1e-3), straight(10, 1));
  EXPECT_FALSE(bad.passed);
  EXPECT_NEAR(bad.min_margin, -1e-3, 1e-6);
  EXPECT_EQ(bad.worst_between, "obstacle wall vs car");
  EXPECT_EQ(bad.worst_between_step, 9);
  ASSERT_EQ(bad.between_shortfalls.count("obstacle wall vs car"), 1u);
  EXPECT_NEAR(bad.between_shortfalls.at("obstacle wall vs car").motion, 0.1, 1e-9);
}

// A thin wall crossed between two samples: every sample is far from it (robust at the samples),
// the flow between them is not.
TEST(RobustCheck, ContinuousTimeSeesAWallCrossedBetweenSamples) {
  Problem p = drive_to_wall(0.0);
  p.tau = 1.0;
  p.obstacles[0].vertices = {{0.45, -1}, {0.55, -1}, {0.55, 1}, {0.45, 1}};
  GlobalPlan g = straight(2, 1);  // x = 0, 1, 2 at the samples
  p.guarantee = Guarantee::Sampled;
  EXPECT_TRUE(check_robust(p, g).passed) << check_robust(p, g).message;
  p.guarantee = Guarantee::Continuous;
  const auto r = check_robust(p, g);
  EXPECT_FALSE(r.passed);
  EXPECT_GE(r.sampled_margin, 0.0);
  EXPECT_LT(r.between_margin, -0.3);  // the eps-box passes through the wall
  EXPECT_EQ(r.worst_between_step, 0);
}

TEST(RobustCheck, PairMarginsAddBothEps) {
  // Two cars side by side, 0.4 + s apart in y: inf-norm delta 0.2 plus 2 x 0.1 needs s >= 0.
  for (double s : {1e-3, -1e-3}) {
    Problem p;
    p.agents.push_back(unicycle("a", {0, 0, 0}));
    p.agents.push_back(unicycle("b", {0, 0.4 + s, 0}));
    p.delta = 0.2;
    const auto r = check_robust(p, straight(5, 2));
    EXPECT_EQ(r.passed, s > 0) << r.message;
    EXPECT_NEAR(r.min_margin, s, 1e-9);
  }
}

namespace {

// A quadrotor in a 3-D workspace coasting at a constant velocity (hover thrust, no torque):
// position p0, velocity v.
AgentSpec coasting_quadrotor(const std::string& name, Eigen::Vector3d p0, Eigen::Vector3d v, double eps) {
  AgentSpec a;
  a.name = name;
  a.dynamics_type = "quadrotor";
  a.dynamics = std::make_shared<models::Quadrotor>();
  a.x0 = Eigen::VectorXd::Zero(12);
  a.x0.head<3>() = p0;
  a.x0.segment<3>(6) = v;
  a.state_bounds = {Eigen::VectorXd::Constant(12, -20), Eigen::VectorXd::Constant(12, 20)};
  a.input_bounds = {Eigen::VectorXd::Constant(4, -20), Eigen::VectorXd::Constant(4, 20)};
  a.goal = a.state_bounds;
  a.tube.eps = Eigen::VectorXd::Constant(12, eps);
  a.tube.w = Eigen::VectorXd::Zero(12);
  a.workspace.index = {0, 1, 2};
  a.workspace.offset = {0, 0, 0};
  return a;
}

GlobalPlan hovering(int T, int agents) {
  GlobalPlan g;
  for (int k = 0; k < T; ++k) {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(4 * agents);
    for (int i = 0; i < agents; ++i) u[4 * i] = 9.81;  // thrust per mass = g: no acceleration
    g.u.push_back(u);
  }
  return g;
}

}  // namespace

// Two quadrotors fly through the same x-y point at the same time, dz apart in height: in space
// they keep delta + both eps (0.2 + 2 x 0.1) only when dz >= 0.4; the plane would call every
// crossing a collision.
TEST(RobustCheck, ThreeDPairsAreJudgedInSpace) {
  for (double dz : {0.4 + 1e-3, 0.4 - 1e-3, 0.15}) {
    Problem p;
    p.workspace_dim = 3;
    p.agents.push_back(coasting_quadrotor("a", {0, 0, 1}, {1, 0, 0}, 0.1));
    p.agents.push_back(coasting_quadrotor("b", {1, 0, 1 + dz}, {-1, 0, 0}, 0.1));
    p.delta = 0.2;
    p.tau = 0.1;
    for (Guarantee g : {Guarantee::Sampled, Guarantee::Continuous}) {
      p.guarantee = g;
      const auto r = check_robust(p, hovering(10, 2));
      EXPECT_EQ(r.passed, dz > 0.4) << r.message;
      EXPECT_NEAR(r.min_margin, dz - 0.4, 1e-6) << r.message;
      if (!r.passed) EXPECT_EQ(r.worst.rfind("collision a vs b", 0), 0u) << r.worst;
    }
  }
}

// Through a window's corner: a slab above z = 1 from x = 1 on. The samples (0.9, 1.3) and
// (1.3, 0.9) are 0.1 from it, but the straight flight between them cuts its corner.
TEST(RobustCheck, ThreeDFlightCuttingAPrismsCornerBetweenSamples) {
  Problem p;
  p.workspace_dim = 3;
  p.agents.push_back(coasting_quadrotor("q", {0.9, 0, 1.3}, {4, 0, -4}, 0.01));
  Obstacle slab;
  slab.name = "slab";
  slab.vertices = {{1, -5}, {5, -5}, {5, 5}, {1, 5}};
  slab.z_lo = 1.0;
  slab.z_hi = 3.0;
  p.obstacles.push_back(slab);
  p.delta = 0.05;
  p.tau = 0.1;
  p.guarantee = Guarantee::Sampled;
  const auto sampled = check_robust(p, hovering(1, 1));
  EXPECT_TRUE(sampled.passed) << sampled.message;
  EXPECT_NEAR(sampled.min_margin, 0.1 - 0.06, 1e-6);
  p.guarantee = Guarantee::Continuous;
  const auto cont = check_robust(p, hovering(1, 1));
  EXPECT_FALSE(cont.passed);
  EXPECT_GE(cont.sampled_margin, 0.0);
  EXPECT_LT(cont.between_margin, -0.1);
  EXPECT_EQ(cont.worst_between, "obstacle slab vs q");
  // Heights matter: the same flight 0.5 m lower passes under the slab.
  p.agents[0] = coasting_quadrotor("q", {0.9, 0, 0.8}, {4, 0, -4}, 0.01);
  EXPECT_TRUE(check_robust(p, hovering(1, 1)).passed);
}

TEST(RobustCheck, RejectsInputsOutsideUAndAMissedGoal) {
  auto p = drive_to_wall(5.0);
  auto u = straight(10, 1);
  u.u[3][0] = 2.0 + 1e-4;
  const auto ru = check_robust(p, u);
  EXPECT_FALSE(ru.passed);
  EXPECT_NEAR(ru.min_input_margin, -1e-4, 1e-12);
  EXPECT_EQ(ru.worst_input, "input bound v of car");
  p.agents[0].goal = {Eigen::Vector3d(1.2, -1, -1), Eigen::Vector3d(2, 1, 1)};  // shrunk: x >= 1.3
  const auto r = check_robust(p, straight(10, 1));
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.worst, "goal x of car");
}

// Between the samples each requirement is first judged on its agents' boxes over the whole
// period and its parts are skipped where that floor decides. The result must be the one every
// part of every requirement gives, bit for bit: random crowded teams (pairs, a formation, a box
// and a polygon obstacle, both norms) whose plans violate and pass, with many near-ties.
namespace {

// A random team of 3-6 unicycles with a box, a triangle and a formation pair, and random inputs;
// every other pair of trials a calm team: spread along x, slow and nearly straight (plans that
// pass, whose minima are positive margins with many near-ties). From trial 40 on, calm teams
// over 40 periods whose agents drive at different speeds: many periods, most of them left out
// by the period floors. (The skipping rule itself is pinned by LowestFirst's made-up floors.)
Problem random_team(std::mt19937& rng, int trial, GlobalPlan& plan) {
  std::uniform_real_distribution<double> pos(-2.0, 2.0), speed(-1.5, 2.0), turn(-3.0, 3.0), ang(-3.0, 3.0);
  Problem p;
  const int N = 3 + trial % 4;
  const bool mixed = trial >= 40, calm = mixed || trial % 4 >= 2;
  for (int i = 0; i < N; ++i)
    p.agents.push_back(unicycle("u" + std::to_string(i), calm ? Eigen::Vector3d(-8.0 + 2.5 * i, 3.0 + 0.3 * pos(rng), mixed ? 0.0 : 1.5)
                                                               : Eigen::Vector3d(pos(rng), pos(rng), ang(rng))));
  Obstacle box;
  box.name = "box";
  box.is_box = true;
  box.vertices = {{0.5, 0.5}, {1.5, 0.5}, {1.5, 1.2}, {0.5, 1.2}};
  Obstacle tri;
  tri.name = "tri";
  tri.vertices = {{-2.0, -1.0}, {-0.8, -1.4}, {-1.2, 0.2}};
  p.obstacles = {box, tri};
  p.formation.push_back({0, 1, calm ? 2.5 : 1.0, calm ? 1.5 : 0.6});
  p.delta = 0.1 + 0.05 * (trial % 3);
  p.delta_norm = trial % 2 ? Norm::Inf : Norm::Two;
  p.tau = 0.2;
  p.horizon = mixed ? 40 : 12;
  plan = GlobalPlan();
  for (int k = 0; k < p.horizon; ++k) {
    Eigen::VectorXd u(2 * N);
    for (int i = 0; i < N; ++i)
      u.segment<2>(2 * i) = mixed  ? Eigen::Vector2d(0.1 + 0.08 * i + 0.03 * speed(rng), 0.05 * turn(rng))
                            : calm ? Eigen::Vector2d(0.4 + 0.1 * speed(rng), 0.1 * turn(rng))
                                   : Eigen::Vector2d(speed(rng), turn(rng));
    plan.u.push_back(u);
  }
  return p;
}

// The smallest margin between the samples on the eps-boxes of the flow itself, `dense` RK4 steps
// per period from every knot (an error far below the 1e-9 the test allows): every point of the
// flow lies in the check's part boxes, so the check can report no more than this.
double dense_between_margin(const Problem& p, const GlobalPlan& plan, int dense) {
  const auto x = rollout(p, plan.u);
  const int N = static_cast<int>(p.agents.size());
  double low = std::numeric_limits<double>::infinity();
  std::vector<Eigen::VectorXd> z(N);
  std::vector<Box> ws(N, Box{Eigen::VectorXd(2), Eigen::VectorXd(2)});
  for (int k = 0; k < p.horizon; ++k) {
    for (int i = 0; i < N; ++i) z[i] = x[k].segment(3 * i, 3);
    for (int j = 0; j <= dense; ++j) {
      for (int i = 0; i < N; ++i) {
        const AgentSpec& a = p.agents[i];
        if (j > 0) {
          Eigen::Vector3d next;
          rk4_step<double>(*a.dynamics, z[i].data(), plan.u[k].data() + 2 * i, nullptr, p.tau / dense, 1, next.data());
          z[i] = next;
        }
        const Box e{z[i] - a.tube.eps, z[i] + a.tube.eps};
        low = std::min(low, box_inside_margin(e, a.state_bounds));
        ws[i].lo = e.lo.head<2>();
        ws[i].hi = e.hi.head<2>();
      }
      for_each_requirement(p, [&](const Requirement& q) { low = std::min(low, box_requirement_margin(p, q, ws)); });
    }
  }
  return low;
}

}  // namespace

TEST(RobustCheck, PeriodFloorsGiveTheEveryPartResultBitForBit) {
  std::mt19937 rng(7);
  int violated = 0, passed = 0, skipped_some = 0;
  for (int trial = 0; trial < 80; ++trial) {
    GlobalPlan plan;
    const Problem p = random_team(rng, trial, plan);
    const MissionSchedule none = schedule_missions(p, p.horizon);
    const RobustCheck fast = check_robust(p, plan, none, RobustCheckOptions{true});
    const RobustCheck ref = check_robust(p, plan, none, RobustCheckOptions{false});
    ASSERT_TRUE(ref.continuous);
    EXPECT_EQ(fast.passed, ref.passed) << trial;
    EXPECT_EQ(fast.min_margin, ref.min_margin) << trial;  // bit for bit
    EXPECT_EQ(fast.worst, ref.worst) << trial;
    EXPECT_EQ(fast.worst_step, ref.worst_step) << trial;
    EXPECT_EQ(fast.worst_agents, ref.worst_agents) << trial;
    EXPECT_EQ(fast.between_margin, ref.between_margin) << trial;
    EXPECT_EQ(fast.worst_between, ref.worst_between) << trial;
    EXPECT_EQ(fast.worst_between_step, ref.worst_between_step) << trial;
    ASSERT_EQ(fast.between_shortfalls.size(), ref.between_shortfalls.size()) << trial;
    for (const auto& [name, b] : ref.between_shortfalls) {
      const auto it = fast.between_shortfalls.find(name);
      ASSERT_NE(it, fast.between_shortfalls.end()) << name;
      EXPECT_EQ(it->second.margin, b.margin) << name;
      EXPECT_EQ(it->second.motion, b.motion) << name;
    }
    EXPECT_EQ(fast.message, ref.message);
    (ref.passed ? passed : violated)++;
    skipped_some += !ref.between_shortfalls.empty();
  }
  // Both outcomes occur, and shortfalls between the samples are compared, not only minima.
  EXPECT_GT(passed, 5);
  EXPECT_GT(violated, 5);
  EXPECT_GT(skipped_some, 5);
}

// Soundness of the boxes between the samples (the parts, each cut to its period's one-part
// enclosure): the check's margin is never above the margin along the flow itself. Both ways the
// floors can be set give the same figure (above), so one is tried.
TEST(RobustCheck, BetweenMarginsAreNeverAboveTheFlowsOwn) {
  std::mt19937 rng(11);
  double closest = std::numeric_limits<double>::infinity();
  for (int trial = 0; trial < 40; ++trial) {
    GlobalPlan plan;
    const Problem p = random_team(rng, trial, plan);
    const RobustCheck r = check_robust(p, plan);
    ASSERT_TRUE(r.continuous);
    const double dense = dense_between_margin(p, plan, 100);
    EXPECT_LE(r.between_margin, dense + 1e-9) << trial << ": " << r.message;
    closest = std::min(closest, dense - r.between_margin);
  }
  // Not vacuous: the check comes within a few millimetres of the flow's own margin somewhere.
  EXPECT_LT(closest, 5e-3);
}

TEST(Assembly, SolverConstraintsAreNoWeakerThanTheCheck) {
  // At a state the check accepts with a small margin, the assembled constraints may reject (they
  // are conservative) but where they accept, the check must accept too.
  Problem p;
  p.agents.push_back(unicycle("a", {0, 0, 0}));
  p.agents.push_back(unicycle("b", {0.45, 0.45, 0}));
  p.delta = 0.2;
  const auto pp = assemble(p, 5, {});
  ASSERT_EQ(pp.constraints.size(), 1u);
  for (double dy : {0.3, 0.4, 0.45, 0.5, 0.6, 0.8}) {
    Eigen::VectorXd x(6);
    x << 0, 0, 0, dy, dy, 0;
    double g;
    pp.constraints[0]->evaluate(x.data(), &g, nullptr);
    p.agents[1].x0 = x.tail(3);
    const auto r = check_robust(p, GlobalPlan{0.1, {}, {}});
    if (g <= 0) EXPECT_TRUE(r.passed) << dy;
  }
  // The Jacobian matches finite differences.
  Eigen::VectorXd x(6);
  x << 0.1, -0.2, 0.3, 0.5, 0.7, -0.1;
  double g, jac[6];
  pp.constraints[0]->evaluate(x.data(), &g, jac);
  for (int i = 0; i < 6; ++i) {
    Eigen::VectorXd y = x;
    y[i] += 1e-6;
    double gy;
    pp.constraints[0]->evaluate(y.data(), &gy, nullptr);
    EXPECT_NEAR((gy - g) / 1e-6, jac[i], 1e-5);
  }
}

TEST(Projector, SplitsTheProductPlan) {
  Problem p;
  p.agents.push_back(unicycle("a", {0, 0, 0}));
  p.agents.push_back(unicycle("b", {0, 2, 0}));
  auto g = straight(3, 2);
  g.x = rollout(p, g.u);
  const auto parts = ProductProjector().project(p, g);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[1].agent, "b");
  EXPECT_EQ(parts[1].x.size(), 4u);
  EXPECT_NEAR(parts[1].x[3][1], 2.0, 1e-12);
  EXPECT_NEAR(parts[1].x[3][0], 0.3, 1e-12);
}

// A crowd's clearance (AssemblyOptions::pair_between_extra, planning/clearance_rounds.hpp) holds
// every pair apart by that much more at the interior points, and leaves the knots' rows alone.
TEST(Assembly, ACrowdsClearanceHoldsEveryPairBetweenTheSamplesOnly) {
  Problem p;
  p.agents.push_back(unicycle("a", {0, 0, 0}));
  p.agents.push_back(unicycle("b", {0.45, 0.45, 0}));
  p.delta = 0.2;
  AssemblyOptions crowd;
  crowd.pair_between_extra = 0.1;
  const auto plain = assemble(p, 5, {}), crowded = assemble(p, 5, crowd);
  auto pair_row = [](const std::vector<std::shared_ptr<const Constraint>>& rows) {
    for (const auto& c : rows)
      if (c->name() == "collision a vs b") return c;
    return std::shared_ptr<const Constraint>();
  };
  Eigen::VectorXd x(6);
  x << 0.1, -0.2, 0.3, 0.5, 0.7, -0.1;
  double g0, g1;
  ASSERT_TRUE(pair_row(plain.constraints) && pair_row(crowded.constraints));
  pair_row(plain.constraints)->evaluate(x.data(), &g0, nullptr);
  pair_row(crowded.constraints)->evaluate(x.data(), &g1, nullptr);
  EXPECT_DOUBLE_EQ(g0, g1);  // the knots: as written
  ASSERT_TRUE(pair_row(plain.between) && pair_row(crowded.between));
  pair_row(plain.between)->evaluate(x.data(), &g0, nullptr);
  pair_row(crowded.between)->evaluate(x.data(), &g1, nullptr);
  EXPECT_NEAR(g1 - g0, 0.1, 1e-12);  // between them: 0.1 more
}
