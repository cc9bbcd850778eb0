// abcd's own rules, asked through the Tracker interface (Tracker::assess / refine) the way the
// loader and the orchestrator ask them: core keeps no copy of the grid convention.
#include <gtest/gtest.h>

#include <cstdlib>

#include "marsyn/core/plugins/plugin_registry.hpp"
#include "marsyn/dynamics.hpp"
#include "marsyn/tracker.hpp"

namespace {

using Eigen::VectorXd;

marsyn::AgentSpec unicycle(const marsyn::PluginRegistry& reg) {
  marsyn::AgentSpec a;
  a.name = "a";
  a.dynamics_type = "unicycle";
  a.dynamics = reg.create<marsyn::Dynamics>("unicycle");
  a.x0 = VectorXd::Zero(3);
  a.x0[1] = 2;
  a.state_bounds = {VectorXd::Constant(3, -1), VectorXd::Constant(3, 11)};
  a.state_bounds.lo[2] = -2;
  a.state_bounds.hi[2] = 3;
  a.input_bounds = {VectorXd::Constant(2, -2), VectorXd::Constant(2, 2)};
  a.goal = {VectorXd::Constant(3, 4.7), VectorXd::Constant(3, 5.3)};
  a.tube.w = VectorXd::Constant(3, 0.02);
  a.tube.eps = (VectorXd(3) << 0.2, 0.2, 0.24).finished();
  a.fields.set("eta_x", (VectorXd(3) << 0.025, 0.025, 0.03).finished());
  a.fields.set("eta_u", VectorXd::Constant(2, 0.3));
  return a;
}

class AbcdAssessment : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!reg.find("tracker", "abcd")) GTEST_SKIP() << "abcd is not built";
    abcd = reg.create<marsyn::Tracker>("abcd");
  }
  marsyn::PluginRegistry reg;
  std::shared_ptr<marsyn::Tracker> abcd;
};

TEST_F(AbcdAssessment, AcceptsAGridInsideTheTubeWithItsFigures) {
  const auto r = abcd->assess(unicycle(reg), 20, 0.1);
  ASSERT_TRUE(r.ok) << r.message;
  // floor(2 eps / eta) = 16 per coordinate, floor(4 / 0.3) + 1 = 14 inputs per input coordinate.
  EXPECT_EQ(r.summary, "<= 4096 tube cells/step, 196 grid inputs");
  // The tables, then the successor cache: the unicycle's field depends on theta alone, so 17
  // columns x 196 inputs, two maps at most half full (8192 slots) and a growing map's old half.
  EXPECT_GT(r.memory_bytes, 21.0 * 4913 * 2 + 2.0 * 4913 * 8 + 196.0 * 3 * 8 + 2.5 * 8192 * 80);
  EXPECT_LT(r.memory_bytes, 21.0 * 4913 * 2 + 2.0 * 4913 * 8 + 196.0 * 3 * 8 + 2.5 * 8192 * 120);
  // Kept: the table (a u16 per cell and step), and 8 period enclosures per step, each about 300
  // bytes with its four vectors' blocks.
  EXPECT_GT(r.kept_bytes, 21.0 * 4913 * 2 + 160 * 250);
  EXPECT_LT(r.kept_bytes, 21.0 * 4913 * 2 + 21 * 200 + 160 * 400);
  EXPECT_DOUBLE_EQ(r.work_s, 1e-8 * 21 * 4096 * 196);
  // More steps, more work: the estimate ranks agents and trackers.
  EXPECT_GT(abcd->assess(unicycle(reg), 40, 0.1).work_s, r.work_s);
}

TEST_F(AbcdAssessment, X0CellOutsideTheTubeNamesTheCoordinate) {
  auto a = unicycle(reg);
  a.fields.find("eta_x")->value[0] = 0.5;
  const auto r = abcd->assess(a, 20, 0.1);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.field, "eta_x");
  EXPECT_EQ(r.coordinate, 0);
  EXPECT_EQ(r.message,
            "x0's grid cell [0, 0.5] in 'x' does not fit inside the tube [x0 - eps, x0 + eps] = [-0.2, 0.2]; choose "
            "eta_x <= eps (0.2)");
}

TEST_F(AbcdAssessment, MissingGridsAreRefusedByName) {
  auto a = unicycle(reg);
  a.fields.find("eta_u")->value.resize(0);
  auto r = abcd->assess(a, 20, 0.1);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.field, "eta_u");
  EXPECT_EQ(r.coordinate, -1);
  EXPECT_NE(r.message.find("the abcd tracker needs 'eta_u'"), std::string::npos) << r.message;
  a = unicycle(reg);
  a.fields.find("eta_x")->value.resize(0);
  r = abcd->assess(a, 20, 0.1);
  EXPECT_EQ(r.field, "eta_x");
  EXPECT_NE(r.message.find("e.g. eps / 8 = [0.025, 0.025, 0.03]"), std::string::npos) << r.message;
  EXPECT_FALSE(abcd->refine(a));
}

TEST_F(AbcdAssessment, MemoryBudgetFromTheRequest) {
  const auto r = abcd->assess(unicycle(reg), marsyn::AssessRequest{20, 0.1, {100 * 1024.0, "--memory-budget"}});
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.field, "eta_x");
  EXPECT_EQ(r.message,
            "the tracker would need about 284954 bytes for this agent (4913 tube cells per step x 21 steps), more "
            "than the memory budget of 102400 bytes (--memory-budget); enlarge eta_x");
}

TEST_F(AbcdAssessment, RefineMakesBothGridsFiner) {
  auto a = unicycle(reg);
  ASSERT_TRUE(abcd->refine(a));
  EXPECT_DOUBLE_EQ(a.fields.value("eta_x")[0], 0.025 * 0.75);
  EXPECT_DOUBLE_EQ(a.fields.value("eta_x")[2], 0.03 * 0.75);
  EXPECT_DOUBLE_EQ(a.fields.value("eta_u")[1], 0.3 * 0.75);
  EXPECT_EQ(a.tube.eps[0], 0.2);  // eps is the orchestrator's, not the tracker's
}

// abcd's grid is its own field: it declares it, and keeps it in step with the tube.
TEST_F(AbcdAssessment, DeclaresItsGridAsAgentFields) {
  const auto specs = abcd->agent_fields();
  ASSERT_EQ(specs.size(), 2u);
  EXPECT_EQ(specs[0].name, "eta_x");
  EXPECT_FALSE(specs[0].per_input);
  EXPECT_EQ(specs[1].name, "eta_u");
  EXPECT_TRUE(specs[1].per_input);
}

TEST_F(AbcdAssessment, ANarrowedTubeKeepsTheStateGridWithinEps) {
  auto a = unicycle(reg);
  a.tube.eps = (VectorXd(3) << 0.02, 0.2, 0.024).finished();
  EXPECT_EQ(abcd->follow_tube(a, marsyn::TubeChange::Narrowed), "");
  const VectorXd eta_x = a.fields.value("eta_x");
  EXPECT_DOUBLE_EQ(eta_x[0], 0.02);   // was 0.025 > eps
  EXPECT_DOUBLE_EQ(eta_x[1], 0.025);  // within eps: unchanged
  EXPECT_DOUBLE_EQ(eta_x[2], 0.024);
  EXPECT_DOUBLE_EQ(a.fields.value("eta_u")[0], 0.3);  // the input grid is not the tube's
  // Setting eps leaves a given grid as written.
  auto b = unicycle(reg);
  b.tube.eps *= 0.1;
  EXPECT_EQ(abcd->follow_tube(b, marsyn::TubeChange::Set), "");
  EXPECT_DOUBLE_EQ(b.fields.value("eta_x")[0], 0.025);
}

TEST_F(AbcdAssessment, AnAutomaticGridFollowsEpsAndU) {
  auto a = unicycle(reg);
  a.fields.find("eta_x")->automatic = true;
  a.fields.find("eta_u")->automatic = true;
  EXPECT_EQ(abcd->follow_tube(a, marsyn::TubeChange::Set),
            "eta_x = 2 eps / 16 (cells per coordinate); eta_u = U's range / 20");
  EXPECT_DOUBLE_EQ(a.fields.value("eta_x")[0], 2 * 0.2 / 16);
  EXPECT_DOUBLE_EQ(a.fields.value("eta_x")[2], 2 * 0.24 / 16);
  EXPECT_DOUBLE_EQ(a.fields.value("eta_u")[1], 4.0 / 20);
}

TEST_F(AbcdAssessment, WarnsWhenTheStateGridIsCoarserThanEps) {
  auto a = unicycle(reg);
  a.fields.find("eta_x")->value[2] = 0.3;
  const auto w = abcd->field_warnings(a);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].rfind("eta_x 0.3 in 'theta' exceeds eps 0.24: no grid cell fits the tube", 0), 0u) << w[0];
}

}  // namespace
