// Bad input to the commands that run the method is answered like bad config: exit code 2 and
// one message naming what is wrong; nothing is written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "run.hpp"

using marsyn::test::run_marsyn;
using marsyn::test::write_temp;

namespace {
const std::string kExample = std::string(MARSYN_SOURCE_DIR) + "/examples/pendulum.yaml";
}

TEST(PipelineErrors, TrackUnknownAgent) {
  const auto r = run_marsyn("track " + kExample + " --agent nosuch");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--agent: no agent named 'nosuch'; agents: pendulum"), std::string::npos) << r.err;
}

TEST(PipelineErrors, TrackMissingPlanFile) {
  const auto r = run_marsyn("track " + kExample + " --agent pendulum --plan /nonexistent/plan.json");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("/nonexistent/plan.json: cannot read the plan file"), std::string::npos) << r.err;
}

TEST(PipelineErrors, TrackPlanOfAnotherProblem) {
  const std::string plan = write_temp("other_plan.json", R"({"agents": [{"name": "drone1", "states": [], "inputs": []}]})");
  const auto r = run_marsyn("track " + kExample + " --agent pendulum --plan " + plan);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("the plan has no agent 'pendulum'"), std::string::npos) << r.err;
}

TEST(PipelineErrors, TrackCorruptPlan) {
  const std::string plan = write_temp("corrupt_plan.json", "{\"agents\": [ {\"name\": ");
  const auto r = run_marsyn("track " + kExample + " --agent pendulum --plan " + plan);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("not a valid JSON plan"), std::string::npos) << r.err;
}

TEST(PipelineErrors, SimulateUnknownDisturbanceMode) {
  const auto r = run_marsyn("simulate " + kExample + " --controllers /tmp --disturbance gusty");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--disturbance: unknown disturbance mode 'gusty'"), std::string::npos) << r.err;
}

TEST(PipelineErrors, SimulateWithoutControllers) {
  const auto r = run_marsyn("simulate " + kExample + " --controllers /nonexistent --disturbance none");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("cannot read the plan file"), std::string::npos) << r.err;
}

TEST(PipelineErrors, SolveMissingConfigWritesNothing) {
  const std::string out = std::filesystem::temp_directory_path() / "marsyn_solve_missing_out";
  std::filesystem::remove_all(out);
  const auto r = run_marsyn("solve /nonexistent/problem.yaml --out " + out);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(PipelineErrors, BenchUnknownStage) {
  const auto r = run_marsyn("bench --stage everything");
  EXPECT_EQ(r.code, 2) << r.err;
}

// planner.warm_start in a config: `marsyn plan` runs the first planner's search, then the main
// planner from its plan, and lists both planners' attempts.
TEST(PlannerChain, ConfigWarmStartRunsBothPlanners) {
  std::ifstream in(kExample);
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const auto pos = yaml.find("\nplanner: altro\n");
  ASSERT_NE(pos, std::string::npos) << "the pendulum example no longer names altro";
  yaml.replace(pos, 16, "\nplanner: {name: altro, warm_start: ipopt}\n");
  const std::string cfg = write_temp("chain.yaml", yaml);
  const std::string out = (std::filesystem::temp_directory_path() / "marsyn_chain_out").string();
  const auto r = run_marsyn("plan " + cfg + " --out " + out);
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("  ipopt T = "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  altro T = "), std::string::npos) << r.out;
  EXPECT_LT(r.out.find("  ipopt T = "), r.out.find("  altro T = ")) << r.out;
  EXPECT_NE(r.err.find("ipopt -> altro: robust plan"), std::string::npos) << r.err;
}
