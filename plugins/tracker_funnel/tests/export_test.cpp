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

std::shared_ptr<const FunnelController> controller(const std::string& scenario) {
  const TrackResult r = FunnelTracker().track(testing::scenario(scenario), {});
  EXPECT_EQ(r.status, TrackerStatus::ControllerFound) << r.message;
  return std::dynamic_pointer_cast<const FunnelController>(r.controller);
}

std::filesystem::path scratch(const std::string& name) {
  return std::filesystem::path(::testing::TempDir()) / ("marsyn_funnel_export_" + name);
}

void expect_identical(const std::string& scenario, int want_kind) {
  const auto c = controller(scenario);
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

TEST(FunnelExportC, UnicycleBitIdenticalWithParallelotopes) { expect_identical("unicycle", kParallelotope); }

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
