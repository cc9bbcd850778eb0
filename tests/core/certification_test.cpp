// The certifier on hand-made enclosures: it must refuse an enclosure that meets an obstacle or
// another agent's enclosure of the same time, accept separated ones, compare parts of periods
// by their time (agents with different part counts), and refuse controllers without enclosures.
#include <gtest/gtest.h>

#include "marsyn/core/verification/certification.hpp"

using namespace marsyn;

namespace {

class BoxController : public Controller {
 public:
  BoxController(int T, std::vector<PeriodEnclosure> e) : T_(T), e_(std::move(e)) {}
  int state_dim() const override { return 2; }
  int input_dim() const override { return 1; }
  int horizon() const override { return T_; }
  ControlStatus input(const double*, int, double*) const override { return ControlStatus::OutsideDomain; }
  void write(const std::string&) const override {}
  const std::vector<PeriodEnclosure>& period_enclosures() const override { return e_; }

 private:
  int T_;
  std::vector<PeriodEnclosure> e_;
};

Box box2(double x0, double y0, double x1, double y1) {
  Box b{Eigen::VectorXd(2), Eigen::VectorXd(2)};
  b.lo << x0, y0;
  b.hi << x1, y1;
  return b;
}

// Agent moving along x from x0 with `parts` parts per period, 0.2 per part, boxes grown by h.
std::shared_ptr<Controller> mover(double x0, double y, int T, int parts, double h) {
  std::vector<PeriodEnclosure> e;
  for (int k = 0; k < T; ++k)
    for (int p = 0; p < parts; ++p) {
      const double x = x0 + 0.2 * (k * parts + p);
      PeriodEnclosure q;
      q.step = k;
      q.t0 = 0.1 * (k + static_cast<double>(p) / parts);
      q.t1 = 0.1 * (k + static_cast<double>(p + 1) / parts);
      q.state = box2(x - h, y - h, x + 0.2 + h, y + h);
      q.workspace = q.state;
      e.push_back(q);
    }
  return std::make_shared<BoxController>(T, e);
}

Problem problem(int agents) {
  Problem pb;
  pb.tau = 0.1;
  pb.delta = 0.1;
  for (int i = 0; i < agents; ++i) {
    AgentSpec a;
    a.name = "a" + std::to_string(i);
    a.state_bounds = box2(-100, -100, 100, 100);
    pb.agents.push_back(a);
  }
  return pb;
}

}  // namespace

TEST(Certification, ObstacleMetBetweenSamplesIsRefused) {
  Problem pb = problem(1);
  Obstacle wall;
  wall.name = "wall";
  wall.vertices = {{1.0, -5}, {1.1, -5}, {1.1, 5}, {1.0, 5}};
  pb.obstacles.push_back(wall);
  const auto r = certify(pb, {mover(0.0, 0.0, 10, 1, 0.01)});
  EXPECT_FALSE(r.certified) << r.message;
  EXPECT_LT(r.obstacle.margin, 0);
  ASSERT_EQ(r.failing_agents.size(), 1u);
  pb.obstacles[0].vertices = {{5.0, -5}, {5.1, -5}, {5.1, 5}, {5.0, 5}};
  const auto ok = certify(pb, {mover(0.0, 0.0, 10, 1, 0.01)});  // the path ends at x = 2.01
  EXPECT_TRUE(ok.certified) << ok.message;
  EXPECT_NEAR(ok.obstacle.margin, 5.0 - 2.01 - 0.1, 1e-12);
}

TEST(Certification, StateBoundsBetweenSamples) {
  Problem pb = problem(1);
  pb.agents[0].state_bounds = box2(-1, -1, 1.5, 1);
  EXPECT_FALSE(certify(pb, {mover(0.0, 0.0, 10, 2, 0.01)}).certified);
  pb.agents[0].state_bounds = box2(-1, -1, 4.02, 1);  // the path ends at 0.4 * 10 + 0.01
  EXPECT_TRUE(certify(pb, {mover(0.0, 0.0, 10, 2, 0.01)}).certified);
}

TEST(Certification, PairsComparedOnOverlappingTimes) {
  Problem pb = problem(2);
  // Same lane, one 0.5 ahead: apart at equal times (0.5 - 0.2 - 2 h > delta), although the
  // follower's later boxes cover the leader's earlier positions.
  {
    const auto r = certify(pb, {mover(0.0, 0.0, 10, 1, 0.05), mover(0.5, 0.0, 10, 2, 0.05)});
    EXPECT_LT(r.collision.margin, 0.5 - 0.2 - 0.1 - pb.delta + 1e-12);
    EXPECT_GT(r.collision.margin, -1e-12) << r.message;
  }
  // 0.3 ahead: the boxes of the same time meet.
  EXPECT_FALSE(certify(pb, {mover(0.0, 0.0, 10, 4, 0.05), mover(0.3, 0.0, 10, 1, 0.05)}).certified);
  pb.pairwise_collision = false;
  EXPECT_TRUE(certify(pb, {mover(0.0, 0.0, 10, 4, 0.05), mover(0.3, 0.0, 10, 1, 0.05)}).certified);
}

TEST(Certification, FormationNeedsBothBounds) {
  Problem pb = problem(2);
  pb.pairwise_collision = false;
  pb.formation.push_back({0, 1, 1.0, 0.3});
  EXPECT_TRUE(certify(pb, {mover(0.0, 0.0, 5, 1, 0.01), mover(0.0, 1.0, 5, 1, 0.01)}).certified);
  pb.formation[0].mu = 0.03;  // the boxes span distances [0.98, |(0.22, 1.02)|] = [0.98, 1.0435]
  EXPECT_FALSE(certify(pb, {mover(0.0, 0.0, 5, 1, 0.01), mover(0.0, 1.0, 5, 1, 0.01)}).certified);
}

TEST(Certification, ControllerWithoutEnclosuresIsRefused) {
  Problem pb = problem(1);
  const auto r = certify(pb, {std::make_shared<BoxController>(5, std::vector<PeriodEnclosure>{})});
  EXPECT_FALSE(r.certified);
  EXPECT_NE(r.message.find("no enclosure"), std::string::npos) << r.message;
}

// Parts of unequal length (allowed by nothing but a careless tracker) are refused: comparing by
// index would pair different times.
TEST(Certification, UnevenPartsAreRefused) {
  Problem pb = problem(2);
  std::vector<PeriodEnclosure> a, b;
  for (int p = 0; p < 2; ++p) {
    PeriodEnclosure e;
    e.step = 0;
    e.t0 = p == 0 ? 0.0 : 0.09;
    e.t1 = p == 0 ? 0.09 : 0.1;
    e.state = e.workspace = box2(10.0 * p, 0, 10.0 * p + 0.1, 0.1);
    a.push_back(e);
    e.t0 = p == 0 ? 0.0 : 0.01;
    e.t1 = p == 0 ? 0.01 : 0.1;
    e.state = e.workspace = box2(p == 0 ? 20.0 : 0.0, 0, (p == 0 ? 20.0 : 0.0) + 0.1, 0.1);
    b.push_back(e);
  }
  const auto r = certify(pb, {std::make_shared<BoxController>(1, a), std::make_shared<BoxController>(1, b)});
  EXPECT_FALSE(r.certified);
  EXPECT_NE(r.message.find("equal parts"), std::string::npos) << r.message;
}
