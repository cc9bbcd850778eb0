// The orchestrator's per-agent trackers: an agent of `tracker: auto` whose tracker answers "no
// controller" moves to the next tracker that accepted it, with the same eps and without a new
// plan, before the Remark 2 search touches it; a tracker named explicitly is never replaced.
// `never` (tests/fixtures/never_tracker.cpp) always answers "no controller" and is the cheapest.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "marsyn/core/report/result_json.hpp"
#include "marsyn/core/solve.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "pendulum_variant.hpp"
#include "quick_solve.hpp"

namespace {

namespace fs = std::filesystem;

std::string pendulum(const std::string& name, const std::string& tracker_line) {
  return marsyn::test::pendulum_variant("fallback_" + name, tracker_line);
}

std::vector<marsyn::Attempt> tracking_attempts(const marsyn::SolveOutcome& o) {
  std::vector<marsyn::Attempt> out;
  for (const auto& a : o.attempts)
    if (a.stage == "track pendulum") out.push_back(a);
  return out;
}

int plans(const marsyn::SolveOutcome& o) {
  int n = 0;
  for (const auto& a : o.attempts) n += a.stage == "plan";
  return n;
}

marsyn::SolveOptions quick(std::vector<std::string>* log = nullptr) { return marsyn::test::quick_solve(log); }

TEST(TrackerFallback, AutoFallsBackBeforeTheEpsSearch) {
  const auto lp = marsyn::load_problem(pendulum("auto", "tracker: auto"));
  ASSERT_EQ(lp.problem.agents[0].tracker.name, "never");
  ASSERT_EQ(lp.trackers.size(), 1u);
  EXPECT_TRUE(lp.trackers[0].automatic);
  // Every other installed tracker that accepts the pendulum, cheapest first: abcd among them.
  const auto& fb = lp.trackers[0].fallbacks;
  ASSERT_TRUE(std::any_of(fb.begin(), fb.end(), [](const auto& c) { return c.name == "abcd"; }));
  // Whatever else the build installs: the solve below falls back to abcd alone.
  marsyn::LoadedProblem only_abcd = lp;
  only_abcd.trackers[0].fallbacks = {{"abcd", {}}};

  const marsyn::SolveOutcome o = marsyn::solve(only_abcd, quick());
  EXPECT_TRUE(o.verified) << o.failure;
  const auto t = tracking_attempts(o);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].parameters, "tracker=never eps=(0.2,0.2) eta_x=(0.01,0.01) eta_u=(0.1)");
  EXPECT_EQ(t[0].outcome, "no controller: the test tracker never finds a controller");
  EXPECT_EQ(t[1].parameters, "tracker=abcd eps=(0.2,0.2) eta_x=(0.01,0.01) eta_u=(0.1)");
  EXPECT_EQ(t[1].outcome.rfind("controller", 0), 0u) << t[1].outcome;
  EXPECT_EQ(plans(o), 1);  // the same eps: the plan stays valid
  ASSERT_EQ(o.agents.size(), 1u);
  EXPECT_EQ(o.agents[0].tracker, "abcd");
  EXPECT_EQ(o.problem.agents[0].tracker.name, "abcd");
  const auto j = marsyn::result_json(o);
  EXPECT_EQ(j["tracker"], "auto");
  EXPECT_EQ(j["agents"][0]["tracker"]["name"], "abcd");
  EXPECT_EQ(j["agents"][0]["tracker"]["chosen"], "auto");
  EXPECT_EQ(j["agents"][0]["tracker"]["status"], "controller");
}

TEST(TrackerFallback, NamedTrackerIsNeverReplaced) {
  const auto lp = marsyn::load_problem(pendulum("named", "tracker: never"));
  EXPECT_FALSE(lp.trackers[0].automatic);
  EXPECT_TRUE(lp.trackers[0].fallbacks.empty());
  marsyn::SolveOptions so = quick();
  so.max_rounds = 2;
  const marsyn::SolveOutcome o = marsyn::solve(lp, so);
  EXPECT_FALSE(o.verified);
  EXPECT_EQ(o.failure, "no controller for pendulum");
  const auto t = tracking_attempts(o);
  ASSERT_EQ(t.size(), 2u);
  // Remark 2: never has nothing to refine, so eps x 1.25 and a new plan; then the round limit.
  EXPECT_EQ(t[0].parameters, "tracker=never eps=(0.2,0.2) eta_x=(0.01,0.01) eta_u=(0.1)");
  EXPECT_EQ(t[1].parameters, "tracker=never eps=(0.25,0.25) eta_x=(0.01,0.01) eta_u=(0.1)");
  EXPECT_EQ(plans(o), 2);
  EXPECT_EQ(marsyn::result_json(o)["agents"][0]["tracker"]["chosen"], "given");
}

// Issue 27 item 3: the budget the loader judged (LoadOptions) is the one the trackers'
// assessment and synthesis receive inside solve(), not a default of their own.
TEST(TrackerFallback, SolveHandsTheLoadedBudgetToAssessmentAndSynthesis) {
  const std::string p = marsyn::test::pendulum_variant("budget", "tracker: never", {{"- name: pendulum", "- name: budget_pendulum"}});
  const auto lp = marsyn::load_problem(p, marsyn::LoadOptions{{1073741824.0, "test"}});
  EXPECT_EQ(lp.memory_budget.bytes, 1073741824.0);
  marsyn::SolveOptions so = quick();
  so.max_rounds = 1;
  const marsyn::SolveOutcome o = marsyn::solve(lp, so);
  ASSERT_EQ(o.agents.size(), 1u);
  EXPECT_NE(o.agents[0].track.message.find("(memory budget: assessed 1073741824, tracked 1073741824)"), std::string::npos)
      << o.agents[0].track.message;
}

}  // namespace
