// A nominal whose input sits at a bound of U (docs/funnel.md, "Inputs at a bound of U"): with
// saturated rows enclosed as boxes the funnel misses the tube; with u_k moved inside U it
// verifies, and the controller applies exactly the moved law it verified. Its soundness is
// sampled with the other models in funnel_soundness_test.cpp ("unicycle_at_bound").
#include <gtest/gtest.h>

#include "funnel_scenarios.hpp"
#include "funnel_tracker.hpp"

namespace marsyn::funnel {
namespace {

TEST(FunnelInputBound, SaturatedBoxesMissTheTubeMovedInputsVerify) {
  const TrackingProblem p = testing::scenario("unicycle_at_bound");
  Params off;
  off.set("shift_inputs", false);
  off.set("input_rounds", 0L);  // input-aware weights verify it without moving u_k (funnel_input_aware_test.cpp)
  const TrackResult boxed = FunnelTracker(off).track(p, {});
  EXPECT_EQ(boxed.status, TrackerStatus::NoController) << boxed.message;
  EXPECT_NE(boxed.message.find("some inputs saturated"), std::string::npos) << boxed.message;

  const TrackResult r = FunnelTracker().track(p, {});
  ASSERT_EQ(r.status, TrackerStatus::ControllerFound) << r.message;
  EXPECT_NE(r.message.find("moved inside U"), std::string::npos) << r.message;
  const FunnelData& d = dynamic_cast<const FunnelController&>(*r.controller).data();
  int moved = 0;
  for (int k = 0; k < d.horizon(); ++k)
    for (int i = 0; i < d.m; ++i) {
      EXPECT_GE(d.u_nom[k][i], d.u_lo[i]);
      EXPECT_LE(d.u_nom[k][i], d.u_hi[i]);
      moved += d.u_nom[k][i] != p.nominal.u[k][i];
    }
  EXPECT_GT(moved, 0);
  // At the stored centre of a moved step the controller answers the moved u_k, not the nominal's.
  for (int k = 0; k < d.horizon(); ++k)
    if (d.u_nom[k][0] != p.nominal.u[k][0] && k > 0) {
      double u[2];
      ASSERT_EQ(r.controller->input(d.x_nom[k].data(), k, u), ControlStatus::Ok) << "step " << k;
      EXPECT_DOUBLE_EQ(u[0], d.u_nom[k][0]);
      break;
    }
}

}  // namespace
}  // namespace marsyn::funnel
