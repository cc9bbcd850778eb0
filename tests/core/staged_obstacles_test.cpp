// Obstacles of one stage (docs/tasks.md, "Obstacles of one stage"): the windows computed from
// the schedule, and the certifier, the spec monitor and the broad phase judging a staged obstacle
// inside its window only. One geometry throughout: a unicycle moving along x at 0.5 per step
// crosses a thin "door" at x in [0.3, 0.5] during period 1 and is far from it from knot 2 on; its
// only stage is visited at knot 2. With `avoid_after` (the door binds from knot 2) everything
// passes; with `avoid` (the door binds on the way, knots 0 to 2) the same motion is refused.
#include <gtest/gtest.h>

#include <random>

#include "../../plugins/dynamics_unicycle/src/unicycle.hpp"
#include "marsyn/core/planning/mission.hpp"
#include "marsyn/core/verification/broad_phase.hpp"
#include "marsyn/core/verification/certification.hpp"
#include "marsyn/core/verification/spec_monitor.hpp"

using namespace marsyn;

namespace {

constexpr int kT = 8, kParts = 4;
constexpr double kSpeed = 0.5, kHalf = 0.05;

class BoxController : public Controller {
 public:
  explicit BoxController(std::vector<PeriodEnclosure> e) : e_(std::move(e)) {}
  int state_dim() const override { return 3; }
  int input_dim() const override { return 2; }
  int horizon() const override { return kT; }
  ControlStatus input(const double*, int, double*) const override { return ControlStatus::OutsideDomain; }
  void write(const std::string&) const override {}
  const std::vector<PeriodEnclosure>& period_enclosures() const override { return e_; }

 private:
  std::vector<PeriodEnclosure> e_;
};

// Part p of period k: the x-interval the motion covers then, grown by kHalf.
std::vector<PeriodEnclosure> moving() {
  std::vector<PeriodEnclosure> e;
  for (int k = 0; k < kT; ++k)
    for (int p = 0; p < kParts; ++p) {
      const double x0 = kSpeed * (k + static_cast<double>(p) / kParts) - kHalf;
      const double x1 = kSpeed * (k + static_cast<double>(p + 1) / kParts) + kHalf;
      PeriodEnclosure q;
      q.step = k;
      q.t0 = 0.1 * (k + static_cast<double>(p) / kParts);
      q.t1 = 0.1 * (k + static_cast<double>(p + 1) / kParts);
      q.state = {Eigen::Vector3d(x0, -kHalf, -0.05), Eigen::Vector3d(x1, kHalf, 0.05)};
      q.workspace = {Eigen::Vector2d(x0, -kHalf), Eigen::Vector2d(x1, kHalf)};
      e.push_back(q);
    }
  return e;
}

enum class Bind { After, OnTheWay };

Problem door_problem(Bind bind) {
  Problem pb;
  pb.tau = 0.1;
  pb.horizon = kT;
  pb.delta = 0.2;
  Obstacle door;
  door.name = "door";
  door.vertices = {{0.3, -1}, {0.5, -1}, {0.5, 1}, {0.3, 1}};
  door.staged = true;
  pb.obstacles.push_back(door);
  AgentSpec a;
  a.name = "car";
  a.dynamics = std::make_shared<models::Unicycle>();
  a.x0 = Eigen::Vector3d(0, 0, 0);
  a.state_bounds = {Eigen::Vector3d(-10, -10, -4), Eigen::Vector3d(10, 10, 4)};
  a.goal = {Eigen::Vector3d(3.7, -0.3, -1), Eigen::Vector3d(4.3, 0.3, 1)};
  a.tube.eps = Eigen::Vector3d(0.1, 0.1, 0.1);
  MissionStage s;
  s.name = "through";
  s.polygon = {{0.7, -0.3}, {1.3, -0.3}, {1.3, 0.3}, {0.7, 0.3}};
  (bind == Bind::After ? s.avoid_after : s.avoid).push_back(0);
  a.stages.push_back(s);
  pb.agents.push_back(a);
  return pb;
}

std::vector<Eigen::VectorXd> states() {
  std::vector<Eigen::VectorXd> x;
  for (int k = 0; k <= kT; ++k) x.push_back(Eigen::Vector3d(kSpeed * k, 0, 0));
  return x;
}

}  // namespace

TEST(StagedObstacles, TheWindowsFollowTheScheduleAndTheLegs) {
  const Problem after = door_problem(Bind::After), way = door_problem(Bind::OnTheWay);
  ASSERT_EQ(planning::schedule_missions(after, kT).visit[0][0], 2);
  const planning::ObstacleWindows wa(after, kT), ww(way, kT);
  EXPECT_EQ(wa.knots(0, 0), (std::vector<int>{2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(ww.knots(0, 0), (std::vector<int>{1, 2}));  // and knot 0, which the planners never see
  EXPECT_TRUE(ww.binds(0, 0, {0, false}));
  EXPECT_FALSE(wa.binds(0, 0, {1, false}));
  EXPECT_FALSE(wa.binds(0, 0, {1, true}));  // knot 2 binds, knot 1 does not: not the period between
  EXPECT_TRUE(wa.binds(0, 0, {2, true}));
  EXPECT_FALSE(wa.binds(0, 0, {8, true}));  // no period after the horizon
  EXPECT_TRUE(ww.binds(0, 0, {1, true}));
  EXPECT_FALSE(ww.binds(0, 0, {2, true}));  // the leg ends at knot 2: not the period after it
  EXPECT_EQ(wa.describe(0, 0), "steps 2-8");
  // An obstacle without the scope binds always, whatever the windows.
  Problem plain = after;
  plain.obstacles[0].staged = false;
  const planning::ObstacleWindows wp(plain, kT);
  EXPECT_FALSE(wp.any());
  for (int k = 0; k <= kT; ++k) EXPECT_TRUE(wp.binds(0, 0, {k, false}));
}

TEST(StagedObstacles, TheCertifierJudgesAStagedObstacleInItsWindowOnly) {
  const auto after = certify(door_problem(Bind::After), {std::make_shared<BoxController>(moving())});
  EXPECT_TRUE(after.certified) << after.message;
  EXPECT_GT(after.obstacle.margin, 0.2);  // from knot 2 on the car is at least 0.45 from the door
  const auto way = certify(door_problem(Bind::OnTheWay), {std::make_shared<BoxController>(moving())});
  EXPECT_FALSE(way.certified) << way.message;
  EXPECT_LT(way.obstacle.margin, 0.0);
  EXPECT_EQ(way.obstacle.where, "obstacle door vs car");
  // The same door for everyone at every time: refused as well.
  Problem plain = door_problem(Bind::After);
  plain.obstacles[0].staged = false;
  plain.agents[0].stages[0].avoid_after.clear();
  EXPECT_FALSE(certify(plain, {std::make_shared<BoxController>(moving())}).certified);
}

TEST(StagedObstacles, TheSpecMonitorJudgesAStagedObstacleInItsWindowOnly) {
  const SpecEvaluation after = SpecMonitor(door_problem(Bind::After)).evaluate(states());
  EXPECT_TRUE(after.satisfied) << after.worst << " " << after.min_margin;
  const SpecEvaluation way = SpecMonitor(door_problem(Bind::OnTheWay)).evaluate(states());
  EXPECT_FALSE(way.satisfied);
  EXPECT_EQ(way.worst, "obstacle door vs car at step 1");
}

// The broad phase skips exactly what the all-pairs check skips: for random teams around staged
// obstacles with random windows, the same minima and the same requirement named at every moment.
TEST(StagedObstacles, TheBroadPhaseAgreesWithTheAllPairsCheckInsideAndOutsideTheWindows) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 6), dt(-0.3, 0.3);
  int differing = 0, checked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    Problem pb;
    pb.tau = 0.1;
    pb.horizon = kT;
    pb.delta = 0.2;
    pb.pairwise_collision = true;
    for (int o = 0; o < 3; ++o) {
      const double x = u(rng), y = u(rng);
      Obstacle ob;
      ob.name = "o" + std::to_string(o);
      ob.vertices = {{x, y}, {x + 0.5, y}, {x + 0.5, y + 0.5}, {x, y + 0.5}};
      ob.staged = o > 0;
      pb.obstacles.push_back(ob);
    }
    for (int i = 0; i < 6; ++i) {
      AgentSpec a;
      a.name = "a" + std::to_string(i);
      a.dynamics = std::make_shared<models::Unicycle>();
      a.x0 = Eigen::Vector3d(u(rng), u(rng), 0);
      a.state_bounds = {Eigen::Vector3d(-10, -10, -4), Eigen::Vector3d(20, 20, 4)};
      a.goal = {Eigen::Vector3d(-10, -10, -4), Eigen::Vector3d(20, 20, 4)};
      a.tube.eps = Eigen::Vector3d(0.1, 0.1, 0.1);
      MissionStage s;
      s.name = "s";
      s.polygon = {{0, 0}, {6, 0}, {6, 6}, {0, 6}};
      if (rng() & 1u) s.avoid.push_back(1);
      if (rng() & 1u) s.avoid_after.push_back(2);
      a.stages.push_back(s);
      pb.agents.push_back(a);
    }
    const SpecMonitor monitor(pb, kT);
    BroadPhase broad(pb);
    broad.windows(&monitor.windows());
    std::vector<marsyn::planning::Point> pts(pb.agents.size());
    Eigen::VectorXd x(3 * static_cast<int>(pb.agents.size()));
    for (int k = 0; k <= kT; ++k)
      for (bool between : {false, true}) {
        for (std::size_t i = 0; i < pts.size(); ++i) {
          pts[i] = marsyn::planning::Point(pb.agents[i].x0[0] + dt(rng) * k, pb.agents[i].x0[1] + dt(rng) * k, 0.0);
          x.segment<3>(3 * static_cast<int>(i)) = Eigen::Vector3d(pts[i].x(), pts[i].y(), 0);
        }
        broad.update(pts);
        std::string name;
        const StepMargins all = monitor.step(x, &name, {k, between});
        StepMargins fast;
        planning::Requirement q{planning::Requirement::Obstacle, -1, -1};
        const bool fell = broad.accumulate(fast, &q, {k, between});
        EXPECT_EQ(all.obstacle, fast.obstacle);
        EXPECT_EQ(all.collision, fast.collision);
        if (fell) EXPECT_EQ(name, q.name(pb));
        // The windowed minimum differs from the unwindowed one somewhere: the windows matter.
        if (monitor.step(x).obstacle != all.obstacle) ++differing;
        ++checked;
      }
  }
  EXPECT_GT(differing, checked / 10);
}
