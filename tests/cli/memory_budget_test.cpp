// The run's memory budget (`--memory-budget`) reaches the trackers' synthesis, not only their
// assessment at load time (issue 27 item 3: synthesis used to judge against an 8e9 default).
// The test tracker `never` (tests/fixtures/never_tracker.cpp) reports, for agents named budget*,
// the budget its track() was given.
#include <gtest/gtest.h>

#include "run.hpp"

using marsyn::test::run_marsyn;
using marsyn::test::write_temp;

namespace {

const std::string kProbe = std::string(R"(name: budget-probe
tau: 0.1
horizon: 20
tracker: never
plugin_paths: [)") + NEVER_TRACKER_DIR + R"(]
agents:
  - name: budget_probe
    dynamics: unicycle
    x0: [0, 2, 0]
    goal: {center: [5, 2, 0], radius: [0.3, 0.3, 0.4]}
    state_bounds: {lo: [-1, -1, -2], hi: [11, 11, 3]}
    input_bounds: {lo: [-2, -2], hi: [2, 2]}
    disturbance: [0, 0.02, 0.02]
    eps: [0.2, 0.2, 0.24]
)";

TEST(MemoryBudget, TrackHandsTheCommandLineBudgetToTheSynthesis) {
  const std::string file = write_temp("budget_probe.yaml", kProbe);
  const auto r = run_marsyn("--memory-budget 1G track " + file + " --agent budget_probe --plan straight-line --out " +
                            file + ".out");
  EXPECT_EQ(r.code, 1) << r.err;  // `never` finds no controller, by design
  EXPECT_NE(r.out.find("tracked 1073741824)"), std::string::npos) << r.out;
}

TEST(MemoryBudget, ABadBudgetIsALocatedErrorBeforeAnyWork) {
  const auto r = run_marsyn("track x.yaml --agent a --memory-budget 12Q");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "--memory-budget: expected a positive number of bytes such as 8e9 or 8G, got '12Q'\n");
}

}  // namespace
