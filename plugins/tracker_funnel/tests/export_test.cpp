// Funnel controllers exported to C (docs/deploy.md): the generated C compiles under gcc -std=c99
// -Wall -Wextra -Werror -pedantic -Wconversion -Wsign-conversion -Wshadow and answers 1e5 sampled
// (x, k) per controller exactly as the C++ controller (status and input bits), and its monitor
// <prefix>_inside exactly as in_set, on controllers with parallelotope and zonotope sets; SCOTS'
// format is refused with the reason.
#include <gtest/gtest.h>

#include "export_compare.hpp"
#include "funnel_scenarios.hpp"
#include "funnel_tracker.hpp"

namespace marsyn::funnel {
namespace {

// verified_set: zonotope stores order-8 zonotopes wherever they certify; the default stores
// parallelotopes.
// invariant: the sets made invariant after the verification (the default), else the forward
// pass's, whose zonotopes all end in the box generators the compact form stores as a diagonal.
std::shared_ptr<const FunnelController> controller(const std::string& scenario, const std::string& verified_set = "zonotope",
                                                   bool invariant = true) {
  Params params;
  params.set("verified_set", verified_set);
  params.set("invariant_sets", invariant);
  const TrackResult r = FunnelTracker(params).track(testing::scenario(scenario), {});
  EXPECT_EQ(r.status, TrackerStatus::ControllerFound) << r.message;
  return std::dynamic_pointer_cast<const FunnelController>(r.controller);
}

std::filesystem::path scratch(const std::string& name) {
  return std::filesystem::path(::testing::TempDir()) / ("marsyn_funnel_export_" + name);
}

void expect_identical(const std::string& scenario, int want_kind, const std::string& verified_set = "zonotope") {
  const auto c = controller(scenario, verified_set);
  ASSERT_TRUE(c);
  int kinds = 0;
  for (const StepSet& s : c->data().sets) kinds += s.kind == want_kind;
  ASSERT_GT(kinds, 0) << scenario << " has no set of kind " << want_kind << ": the test would not exercise it";
  const auto r = testing::compare_export(*c, scratch(scenario), scenario, 100000, 7);
  ASSERT_EQ(r.error, "");
  EXPECT_EQ(r.mismatches, 0) << r.first_mismatches;
  EXPECT_EQ(r.queries, 100000);
  EXPECT_GT(r.status[0], 10000);  // Ok
  EXPECT_GT(r.status[1], 10000);  // OutsideDomain
  EXPECT_GT(r.status[2], 2000);   // OutsideHorizon
  EXPECT_GT(r.inside, 10000);
  EXPECT_GT(r.outside, 10000);
  EXPECT_GT(r.boundary, 5000);
  EXPECT_EQ(r.const_bytes, c_const_bytes(c->data()));
}

TEST(FunnelExportC, BicycleBitIdenticalWithZonotopes) { expect_identical("bicycle", kZonotope); }

TEST(FunnelExportC, UnicycleBitIdenticalWithParallelotopes) { expect_identical("unicycle", kParallelotope, "parallelotope"); }

// The unicycle's heading is periodic: read whole turns away, the C answers as the C++ (the same
// lift onto x_k's branch) and most states near V_k's centre are still accepted; read as written
// they would all be refused.
TEST(FunnelExportC, UnicycleReadsItsHeadingOnAnyBranch) {
  const auto c = controller("unicycle", "parallelotope");
  ASSERT_TRUE(c);
  ASSERT_EQ(c->data().periodic, (std::vector<std::uint8_t>{0, 0, 1}));
  const auto r = testing::compare_export(*c, scratch("unicycle_turned"), "unicycle", 40000, 8, true);
  ASSERT_EQ(r.error, "");
  EXPECT_EQ(r.mismatches, 0) << r.first_mismatches;
  EXPECT_GT(r.status[0], 4000);  // Ok
  EXPECT_GT(r.inside, 4000);
}

// The compact tables (box_k recomputed from x_k and eps, axis generators stored as their
// diagonal) are used only where they reproduce the file's bits; elsewhere the C stores the numbers
// as they are. Forcing those fallbacks (a -0.0 off the diagonal, a bound one ulp inward) must
// still answer bit for bit, through the other code paths; steps whose V_k is box_k itself put the
// recomputed bounds to the test on the faces (elsewhere V_k lies strictly inside box_k).
TEST(FunnelExportC, StoredBoxesAndDenseGeneratorsWhereTheCompactFormsDoNotApply) {
  // The forward pass's sets: the byte count below assumes every zonotope's last n generators are
  // the axis box (an invariant chain's set may have lost a zero one).
  const auto c = controller("bicycle", "zonotope", false);
  ASSERT_TRUE(c);
  FunnelData d = c->data();
  int forced_dense = 0, forced_box = 0, box_only = 0;
  for (int k = 1; k < static_cast<int>(d.sets.size()); ++k) {
    StepSet& s = d.sets[static_cast<size_t>(k)];
    if (k % 3 == 1) {  // V_k = box_k: the recomputed eps-box alone decides, faces included
      s = StepSet{s.lo, s.hi};
      ++box_only;
      continue;
    }
    if (s.kind == kZonotope && k % 2 == 0) {
      s.S[static_cast<size_t>((s.generators - 1) * d.n)] = -0.0;  // last generator, first row
      ++forced_dense;
    }
    if (k % 3 == 0) {
      s.lo[1] = std::nextafter(s.lo[1], INFINITY);
      ++forced_box;
    }
  }
  ASSERT_GT(box_only, 3);
  ASSERT_GT(forced_dense, 3);
  const FunnelController modified(d);
  FunnelData boxes_only = c->data();  // the same box-only steps, compact forms everywhere else
  for (int k = 1; k < static_cast<int>(d.sets.size()); k += 3) boxes_only.sets[static_cast<size_t>(k)] = d.sets[static_cast<size_t>(k)];
  EXPECT_EQ(c_const_bytes(d), c_const_bytes(boxes_only) + forced_dense * 8 * d.n * (d.n - 1) + forced_box * 16 * d.n);
  const auto r = testing::compare_export(modified, scratch("fallbacks"), "fallbacks", 100000, 8);
  ASSERT_EQ(r.error, "");
  EXPECT_EQ(r.mismatches, 0) << r.first_mismatches;
  EXPECT_GT(r.inside, 10000);
  EXPECT_GT(r.boundary, 5000);
}

TEST(FunnelExportC, ScsIsRefusedWithTheReasonAndBadRequestsAreErrors) {
  const auto c = controller("unicycle");
  ASSERT_TRUE(c);
  const auto dir = scratch("bad");
  std::filesystem::remove_all(dir);
  ExportRequest req;
  req.out_dir = dir.string();
  req.format = "scs";
  ExportResult r = c->export_to(req);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("funnel controller has no grid"), std::string::npos) << r.message;
  EXPECT_EQ(r.message.find('\n'), std::string::npos);
  req.format = "c";
  req.prefix = "9lives";
  r = c->export_to(req);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("not a C identifier"), std::string::npos) << r.message;
  req.prefix = "ok";
  req.encoding = "zip";
  EXPECT_FALSE(c->export_to(req).ok);
  EXPECT_FALSE(std::filesystem::exists(dir));
}

}  // namespace
}  // namespace marsyn::funnel
