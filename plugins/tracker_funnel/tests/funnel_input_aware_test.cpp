// Input-aware weights (docs/funnel.md, "Input-aware weights"): a nominal whose speed runs just
// inside U, under 4x the test disturbance, where every weight of the ladder encloses the speed
// row as a saturated box and misses the tube; redesigned with R raised where the verified input
// hull left U, it verifies. Its soundness is sampled with the other models in
// funnel_soundness_test.cpp ("unicycle_near_bound").
#include <gtest/gtest.h>

#include "funnel_scenarios.hpp"
#include "funnel_tracker.hpp"
#include "input_weights.hpp"
#include "lqr.hpp"

namespace marsyn::funnel {
namespace {

Params without_splits(long rounds) {
  Params p;
  p.set("split_depth", 0L);  // splitting alone verifies this agent too (docs/funnel.md): kept out
  p.set("input_rounds", rounds);
  return p;
}

TEST(FunnelInputAware, SaturatedLadderMissesInputAwareWeightsVerify) {
  const TrackingProblem p = testing::scenario("unicycle_near_bound");
  const TrackResult ladder = FunnelTracker(without_splits(0)).track(p, {});
  ASSERT_EQ(ladder.status, TrackerStatus::NoController) << ladder.message;
  EXPECT_NE(ladder.message.find("some inputs saturated"), std::string::npos) << ladder.message;
  EXPECT_GT(ladder.failure.input_saturation, 0.0);

  const TrackResult r = FunnelTracker(without_splits(5)).track(p, {});
  ASSERT_EQ(r.status, TrackerStatus::ControllerFound) << r.message;
  EXPECT_NE(r.message.find("input-aware weights"), std::string::npos) << r.message;
  // The controller applies gains softer than the ladder's first choice on the speed row where
  // the nominal runs near U's bound (t in [1.5, 4.8] s here).
  const FunnelData& d = dynamic_cast<const FunnelController&>(*r.controller).data();
  LqrWeights wt;
  wt.q.resize(3);
  wt.r.resize(2);
  for (int i = 0; i < 3; ++i) wt.q[i] = 1.0 / (p.tube.eps[i] * p.tube.eps[i]);
  for (int j = 0; j < 2; ++j) wt.r[j] = 1.0 / (2.4 * 2.4);
  const LqrGains plain = lqr_gains(*p.dynamics, p.nominal, p.tau, 4, wt);
  ASSERT_TRUE(plain.ok());
  int softer = 0;
  for (int k = 0; k < d.horizon(); ++k)
    if (p.nominal.u[k][0] > 2.3) {
      double a = 0.0, b = 0.0;
      for (int j = 0; j < 3; ++j) {
        a += std::fabs(d.K[k][j]);
        b += std::fabs(plain.K[k](0, j));
      }
      softer += a < 0.5 * b;
    }
  EXPECT_GT(softer, 5);
}

// The nominal whose speed sits at U's bound (FunnelInputBound): with u_k never moved inside U,
// the ladder's saturated boxes miss the tube, and input-aware weights verify it.
TEST(FunnelInputAware, AtTheBoundWithoutMovingInputs) {
  const TrackingProblem p = testing::scenario("unicycle_at_bound");
  Params off = without_splits(0);
  off.set("shift_inputs", false);
  const TrackResult ladder = FunnelTracker(off).track(p, {});
  EXPECT_EQ(ladder.status, TrackerStatus::NoController) << ladder.message;
  off.set("input_rounds", 5L);
  const TrackResult r = FunnelTracker(off).track(p, {});
  ASSERT_EQ(r.status, TrackerStatus::ControllerFound) << r.message;
  EXPECT_NE(r.message.find("input-aware weights"), std::string::npos) << r.message;
  EXPECT_EQ(r.message.find("moved inside U"), std::string::npos) << r.message;
}

// A miss caused by saturation says which input, on which steps and how far its hull left U.
TEST(FunnelInputAware, AMissNamesTheSaturatedInputItsStepsAndItsExcess) {
  const TrackingProblem p = testing::scenario("unicycle_near_bound");
  Params once = without_splits(0);
  once.set("weight_search", false);
  const TrackResult r = FunnelTracker(once).track(p, {});
  ASSERT_EQ(r.status, TrackerStatus::NoController) << r.message;
  // "some inputs saturated: v on N step(s) (a-b), its hull up to X past U (step s)"
  const auto at = r.message.find("some inputs saturated: v on ");
  ASSERT_NE(at, std::string::npos) << r.message;
  const std::string rest = r.message.substr(at);
  EXPECT_NE(rest.find(" step(s) ("), std::string::npos) << rest;
  EXPECT_NE(rest.find("its hull up to "), std::string::npos) << rest;
  EXPECT_NE(rest.find(" past U (step "), std::string::npos) << rest;
  EXPECT_EQ(rest.find("omega"), std::string::npos) << "the turn rate stays inside U here: " << rest;
  // The excess is the hull's, positive, and no more than the hull can reach (|K| times the tube).
  const double excess = std::stod(rest.substr(rest.find("its hull up to ") + 15));
  EXPECT_GT(excess, 0.0);
  EXPECT_LT(excess, 10.0);
}

// The re-weighting itself: a hull past U's upper bound at one step raises R there only, by the
// amount that scales the row's gain to fit, and leaves the other steps and inputs alone.
TEST(FunnelInputAware, WeightsRiseWhereTheHullLeavesUAndOnlyThere) {
  const TrackingProblem p = testing::scenario("unicycle_near_bound");
  LqrWeights wt;
  wt.q = Eigen::VectorXd::Constant(3, 25.0);
  wt.r = Eigen::VectorXd::Constant(2, 0.17);
  const LqrGains g = lqr_gains(*p.dynamics, p.nominal, p.tau, 4, wt);
  ASSERT_TRUE(g.ok());
  const int T = static_cast<int>(p.nominal.u.size());
  VerifyOutcome v;
  v.input_hull.resize(T);
  for (int k = 0; k < T; ++k)
    for (int i = 0; i < 2; ++i) {
      const double u = p.nominal.u[k][i];
      v.input_hull[k].push_back(FastInterval(u - 0.01, u + 0.01));
    }
  const int k0 = 5;
  const double u0 = p.nominal.u[k0][0];
  const double room = 2.4 - u0;
  ASSERT_GT(room, 0.05);
  v.input_hull[k0][0] = FastInterval(u0 - 2 * room, u0 + 2 * room);  // twice the room above u_k
  std::vector<Eigen::VectorXd> r;
  const InputReweighting rw = input_aware_weights(p, g, v, r, 0.05, 0.9);
  EXPECT_EQ(rw.rows, 1);
  EXPECT_EQ(rw.first_step, k0);
  ASSERT_EQ(static_cast<int>(r.size()), T);
  for (int k = 0; k < T; ++k)
    for (int i = 0; i < 2; ++i)
      if (k != k0 || i != 0) EXPECT_EQ(r[k][i], g.r[k][i]) << k << " " << i;
  // Scale 0.45 (half the room, times the margin 0.9): R_k = (R + b) / 0.45 - b.
  const double b = g.bpb[k0][0];
  EXPECT_NEAR(r[k0][0], (g.r[k0][0] + b) / 0.45 - b, 1e-12 * r[k0][0]);
}

}  // namespace
}  // namespace marsyn::funnel
