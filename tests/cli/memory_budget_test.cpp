// The run's memory budget (`--memory-budget`) reaches the trackers' synthesis, not only their
// assessment at load time (issue 27 item 3: synthesis used to judge against an 8e9 default).
// The test tracker `never` (tests/fixtures/never_tracker.cpp) reports, for agents named budget*,
// the budget its track() was given.
#include <gtest/gtest.h>

#include "one_unicycle.hpp"
#include "run.hpp"

using marsyn::test::run_marsyn;
using marsyn::test::write_temp;

namespace {

const std::string kProbe = marsyn::test::one_unicycle(
    std::string("tracker: never\nplugin_paths: [") + NEVER_TRACKER_DIR + "]", "budget_probe");

TEST(MemoryBudget, TrackHandsTheCommandLineBudgetToTheSynthesis) {
  const std::string file = write_temp("budget_probe.yaml", kProbe);
  const auto r = run_marsyn("--memory-budget 1G track " + file + " --agent budget_probe --plan straight-line --out " +
                            file + ".out");
  EXPECT_EQ(r.code, 1) << r.err;  // `never` finds no controller, by design
  EXPECT_NE(r.out.find("tracked 1073741824)"), std::string::npos) << r.out;
}

// The same through `marsyn solve`: the loader, the tracker's assessment and every round's
// synthesis (track_agents) judge the one budget given on the command line.
TEST(MemoryBudget, SolveHandsTheCommandLineBudgetToTheSynthesis) {
  const std::string file = write_temp("budget_probe_solve.yaml", kProbe);
  const auto r = run_marsyn("--memory-budget 1G solve " + file + " --time-limit 5 --out " + file + ".solve");
  EXPECT_EQ(r.code, 1) << r.err;  // `never` finds no controller, by design
  // the tracker's message reaches result.json, not the summary
  const std::string result = marsyn::test::slurp(file + ".solve/result.json");
  EXPECT_NE(result.find("(memory budget: assessed 1073741824, tracked 1073741824)"), std::string::npos) << result;
}

TEST(MemoryBudget, ABadBudgetIsALocatedErrorBeforeAnyWork) {
  const auto r = run_marsyn("track x.yaml --agent a --memory-budget 12Q");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "--memory-budget: expected a positive number of bytes such as 8e9 or 8G, got '12Q'\n");
}

}  // namespace
