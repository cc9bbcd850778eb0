// The plan's progress line (core/planning/solver_progress.hpp): quiet for short solves, redrawn
// at most ten times a second on a terminal, the last measured violation carried between
// iterations that do not measure it.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "marsyn/core/planning/solver_progress.hpp"

using marsyn::PlanProgress;
using marsyn::planning::SolverProgress;

TEST(SolverProgress, ALiveLineCarriesTheLastMeasuredViolation) {
  std::vector<std::string> live, log;
  SolverProgress p([&](const std::string& s) { log.push_back(s); }, [&](const std::string& s) { live.push_back(s); });
  p(PlanProgress{1, 100.0, 0.25});
  EXPECT_TRUE(live.empty());  // within the first tenth of a second: nothing drawn yet
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  p(PlanProgress{7, 42.5, -1.0});  // an inner iteration: no violation measured
  ASSERT_EQ(live.size(), 1u);
  EXPECT_NE(live[0].find("iteration 7"), std::string::npos) << live[0];
  EXPECT_NE(live[0].find("cost 42.5"), std::string::npos) << live[0];
  EXPECT_NE(live[0].find("violation 0.25"), std::string::npos) << live[0];
  p(PlanProgress{8, 40.0, -1.0});  // again within a tenth of a second of the last redraw
  EXPECT_EQ(live.size(), 1u);
  EXPECT_TRUE(log.empty());  // a terminal gets the live line only
}

TEST(SolverProgress, WithoutATerminalAShortSolveSaysNothing) {
  std::vector<std::string> log;
  SolverProgress p([&](const std::string& s) { log.push_back(s); }, {});
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  for (int i = 0; i < 50; ++i) p(PlanProgress{i, 1.0, 0.1});
  EXPECT_TRUE(log.empty());  // one line every 10 s at most
}
