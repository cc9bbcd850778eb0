// The certifier on a mission stage (docs/tasks.md): the region at the visit knots on the
// enclosures of the sampling instants, and between the knots while the stage dwells, on
// hand-made enclosures. An enclosure that leaves the region between two samples of the dwell
// must be refused even though every sample is inside.
#include <gtest/gtest.h>

#include "../../plugins/dynamics_unicycle/src/unicycle.hpp"
#include "marsyn/core/verification/certification.hpp"

using namespace marsyn;

namespace {

class BoxController : public Controller {
 public:
  BoxController(int T, std::vector<PeriodEnclosure> e) : T_(T), e_(std::move(e)) {}
  int state_dim() const override { return 3; }
  int input_dim() const override { return 2; }
  int horizon() const override { return T_; }
  ControlStatus input(const double*, int, double*) const override { return ControlStatus::OutsideDomain; }
  void write(const std::string&) const override {}
  const std::vector<PeriodEnclosure>& period_enclosures() const override { return e_; }

 private:
  int T_;
  std::vector<PeriodEnclosure> e_;
};

constexpr int kT = 8, kParts = 4;

// Every part of every period: the box (x +- h) x (0 +- h) x (0 +- 0.1).
std::vector<PeriodEnclosure> parked(double x, double h) {
  std::vector<PeriodEnclosure> e;
  for (int k = 0; k < kT; ++k)
    for (int p = 0; p < kParts; ++p) {
      PeriodEnclosure q;
      q.step = k;
      q.t0 = 0.1 * (k + static_cast<double>(p) / kParts);
      q.t1 = 0.1 * (k + static_cast<double>(p + 1) / kParts);
      q.state = {Eigen::Vector3d(x - h, -h, -0.1), Eigen::Vector3d(x + h, h, 0.1)};
      q.workspace = {Eigen::Vector2d(x - h, -h), Eigen::Vector2d(x + h, h)};
      e.push_back(q);
    }
  return e;
}

// One unicycle from (0, 0) to the goal (4, 0), visiting the square of half-width 0.3 around
// (1, 0) at knot 2 (a quarter of the 7 steps of travel, rounded) and dwelling one step.
Problem mission() {
  Problem pb;
  pb.tau = 0.1;
  pb.horizon = kT;
  AgentSpec a;
  a.name = "car";
  a.dynamics = std::make_shared<models::Unicycle>();
  a.x0 = Eigen::Vector3d(0, 0, 0);
  a.state_bounds = {Eigen::Vector3d(-10, -10, -4), Eigen::Vector3d(10, 10, 4)};
  a.goal = {Eigen::Vector3d(3.7, -0.3, -1), Eigen::Vector3d(4.3, 0.3, 1)};
  a.tube.eps = Eigen::Vector3d(0.1, 0.1, 0.1);
  MissionStage s;
  s.name = "pickup";
  s.polygon = {{0.7, -0.3}, {1.3, -0.3}, {1.3, 0.3}, {0.7, 0.3}};
  s.dwell = 1;
  a.stages.push_back(s);
  pb.agents.push_back(a);
  return pb;
}

}  // namespace

TEST(MissionCertification, TheRegionIsCertifiedAtTheKnotsAndBetweenThem) {
  const Problem pb = mission();
  const auto ok = certify(pb, {std::make_shared<BoxController>(kT, parked(1.0, 0.05))});
  EXPECT_TRUE(ok.certified) << ok.message;
  ASSERT_EQ(ok.stages.size(), 1u);
  EXPECT_EQ(ok.stages[0].step, 2);
  EXPECT_NEAR(ok.stages[0].margin, 0.25, 1e-12);
  EXPECT_NEAR(ok.stages[0].between_margin, 0.25, 1e-12);
  // Parked outside the region: refused at the samples.
  const auto out = certify(pb, {std::make_shared<BoxController>(kT, parked(2.0, 0.05))});
  EXPECT_FALSE(out.certified);
  EXPECT_LT(out.stages[0].sampled_margin, 0);
  EXPECT_EQ(out.stage.where, "stage pickup of car");
}

TEST(MissionCertification, LeavingTheRegionBetweenTheSamplesOfTheDwellIsRefused) {
  const Problem pb = mission();
  auto e = parked(1.0, 0.05);
  // Period 2 (from knot 2 to knot 3, the dwell): its second part swings out to x = 1.4.
  e[2 * kParts + 1].state.hi[0] = 1.4;
  e[2 * kParts + 1].workspace.hi[0] = 1.4;
  const auto r = certify(pb, {std::make_shared<BoxController>(kT, e)});
  EXPECT_FALSE(r.certified) << r.message;
  EXPECT_NEAR(r.stages[0].sampled_margin, 0.25, 1e-12);  // every sample inside
  EXPECT_NEAR(r.stages[0].between_margin, -0.1, 1e-12);
  ASSERT_EQ(r.failing_agents.size(), 1u);
  EXPECT_TRUE(r.shortfalls.count("stage pickup of car"));
  // The same swing outside the dwell (period 5) concerns no stage.
  auto later = parked(1.0, 0.05);
  later[5 * kParts + 1].state.hi[0] = 1.4;
  later[5 * kParts + 1].workspace.hi[0] = 1.4;
  EXPECT_TRUE(certify(pb, {std::make_shared<BoxController>(kT, later)}).certified);
  // The enclosure of knot 3 is the intersection of the part ending there and the part starting
  // there: a wide last part of period 2 alone does not fail the sample.
  auto wide = parked(1.0, 0.05);
  wide[3 * kParts - 1].state.hi[0] = 1.4;
  wide[3 * kParts - 1].workspace.hi[0] = 1.4;
  const auto w = certify(pb, {std::make_shared<BoxController>(kT, wide)});
  EXPECT_NEAR(w.stages[0].sampled_margin, 0.25, 1e-12);
  EXPECT_LT(w.stages[0].between_margin, 0);
}

// The certifier judges the stages at the plan's knots (given as the problem at those knots,
// planning::with_visits, as the search and `marsyn verify` give it): controllers inside the
// region from knot 5 to 6 are certified at a plan's knot 5, and the same controllers are refused
// at knot 2 (the initial schedule's), i.e. a plan whose knots were changed after the fact.
TEST(MissionCertification, TheStagesAreJudgedAtThePlansKnots) {
  const Problem pb = mission();
  auto e = parked(2.0, 0.05);
  for (int k = 4; k <= 6; ++k)
    for (int p = 0; p < kParts; ++p) {
      PeriodEnclosure& q = e[static_cast<std::size_t>(k * kParts + p)];
      q.state.lo[0] = q.workspace.lo[0] = 0.95;
      q.state.hi[0] = q.workspace.hi[0] = 1.05;
    }
  const auto ctrl = std::make_shared<BoxController>(kT, e);
  const planning::MissionSchedule at5{{{5}}, kT};
  const auto chosen = certify(planning::with_visits(pb, at5), {ctrl});
  EXPECT_TRUE(chosen.certified) << chosen.message;
  ASSERT_EQ(chosen.stages.size(), 1u);
  EXPECT_EQ(chosen.stages[0].step, 5);
  EXPECT_NEAR(chosen.stages[0].margin, 0.25, 1e-12);
  const planning::MissionSchedule at2{{{2}}, kT};
  const auto moved = certify(planning::with_visits(pb, at2), {ctrl});
  EXPECT_FALSE(moved.certified);
  EXPECT_EQ(moved.stages[0].step, 2);
  EXPECT_EQ(moved.stage.where, "stage pickup of car");
}
