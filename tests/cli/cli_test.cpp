#include <gtest/gtest.h>

#include <unistd.h>

#include "run.hpp"

using marsyn::test::run_marsyn;

TEST(Cli, VersionAndHelp) {
  auto v = run_marsyn("--version");
  EXPECT_EQ(v.code, 0);
  EXPECT_NE(v.out.find("marsyn 0."), std::string::npos);
  auto h = run_marsyn("--help");
  EXPECT_EQ(h.code, 0);
  EXPECT_NE(h.out.find("plugins"), std::string::npos);
  EXPECT_NE(h.out.find("check"), std::string::npos);
}

TEST(Cli, UnknownSubcommandIsExitTwo) {
  auto r = run_marsyn("frobnicate");
  EXPECT_EQ(r.code, 2);
  EXPECT_FALSE(r.err.empty());
}

TEST(Cli, PluginsListsTheFourDynamicsModels) {
  auto r = run_marsyn("plugins");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* name : {"unicycle", "cartpole", "double_integrator", "pendulum"}) {
    EXPECT_NE(r.out.find(name), std::string::npos) << name;
  }
  EXPECT_NE(r.out.find("libmarsyn_dynamics_unicycle.so"), std::string::npos);
}

TEST(Cli, PluginsWarnsAboutALibraryOfAnotherApiVersion) {
  auto r = run_marsyn("plugins", std::string("MARSYN_PLUGIN_PATH=") + OTHER_API_PLUGIN_DIR);
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.err.find("API version 999"), std::string::npos) << r.err;
}

class Examples : public ::testing::TestWithParam<const char*> {};

TEST_P(Examples, CheckAcceptsAndSummarizes) {
  auto r = run_marsyn(std::string("check ") + MARSYN_SOURCE_DIR + "/examples/" + GetParam());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("product system"), std::string::npos);
  EXPECT_NE(r.out.find("constraints per step"), std::string::npos);
  EXPECT_NE(r.out.find("is a valid marsyn problem"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(CaseStudies, Examples,
                         ::testing::Values("multi_drone.yaml", "crane_vehicle.yaml", "lane_merging.yaml",
                                           "formation.yaml", "pendulum.yaml", "crane_vehicle_swing.yaml",
                                           "global_baseline.yaml"));

TEST(Cli, MultiDroneSummaryHasTheProductDimensions) {
  auto r = run_marsyn(std::string("check ") + MARSYN_SOURCE_DIR + "/examples/multi_drone.yaml");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("30 states, 20 inputs"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("collision 45"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("obstacle 10"), std::string::npos) << r.out;
}
