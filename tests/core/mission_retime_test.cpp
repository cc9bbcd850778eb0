// The plan chooses its visit knots (docs/tasks.md, "What is planned"): on a mission whose
// distance-proportional schedule the robot cannot meet at its horizon, the re-timed knots can; a
// knot the user fixed stays; the knots are written to plan.json and read back as they were.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "marsyn/core/planning/plan_io.hpp"
#include "marsyn/core/problem/config_error.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/setup.hpp"

using namespace marsyn;

namespace {

const std::string kCorridor = std::string(MARSYN_SOURCE_DIR) + "/tests/core/mission_retime/corridor.yaml";

planning::PlanSearchOptions search(int retime_rounds, int horizons) {
  planning::PlanSearchOptions o;
  o.retime_rounds = retime_rounds;
  o.max_attempts = horizons;
  return o;
}

std::filesystem::path scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("marsyn_mission_retime_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir / name;
}

}  // namespace

// corridor.yaml: the initial schedule visits the corridor at knot 18 of 40; the robot cannot then
// reach its dock by T = 40, and with the knots fixed only a longer horizon gives a plan. Re-timed
// along the failed plan, the visit moves earlier and T = 40 suffices.
TEST(MissionRetime, ChosenKnotsSolveWhatTheFixedScheduleCannot) {
  marsyn::Setup setup(load_problem(kCorridor));
  const Problem& pb = setup.problem();
  const planning::PlanOutcome fixed = setup.plan(search(0, 1));
  EXPECT_FALSE(fixed.feasible) << fixed.check.message;
  EXPECT_EQ(fixed.visits.visit, (std::vector<std::vector<int>>{{18}}));
  const planning::PlanOutcome longer = setup.plan(search(0, 4));
  ASSERT_TRUE(longer.feasible) << longer.check.message;
  EXPECT_GT(longer.horizon, 40);
  const planning::PlanOutcome chosen = setup.plan(search(3, 1));
  ASSERT_TRUE(chosen.feasible) << chosen.check.message;
  EXPECT_EQ(chosen.horizon, 40);
  EXPECT_EQ(chosen.visits.horizon, 40);
  EXPECT_LT(chosen.visits.visit[0][0], 18);
  ASSERT_EQ(chosen.check.stages.size(), 1u);
  EXPECT_EQ(chosen.check.stages[0].step, chosen.visits.visit[0][0]);
  EXPECT_TRUE(planning::check_robust(pb, chosen.plan, chosen.visits).passed);
}

// A knot the user fixed (not_before == by) is never re-timed: the search keeps it at every
// horizon and lengthens the horizon instead.
TEST(MissionRetime, AUserFixedKnotNeverMoves) {
  LoadedProblem lp = load_problem(kCorridor);
  MissionStage& st = lp.problem.agents[0].stages[0];
  st.not_before = st.by = 18;
  marsyn::Setup setup(std::move(lp));
  const planning::PlanOutcome o = setup.plan(search(3, 4));
  ASSERT_TRUE(o.feasible) << o.check.message;
  EXPECT_GT(o.horizon, 40);
  EXPECT_EQ(o.visits.visit, (std::vector<std::vector<int>>{{18}}));
  for (const auto& a : o.attempts) EXPECT_EQ(a.visits.visit, (std::vector<std::vector<int>>{{18}})) << a.horizon;
}

// plan.json carries the knots: read back as written; a plan written without them (before they
// were part of it) reads as the initial schedule; knots that are no schedule are a located error.
TEST(MissionRetime, TheSavedPlanRoundTripsItsKnots) {
  marsyn::Setup setup(load_problem(kCorridor));
  const Problem& pb = setup.problem();
  const planning::PlanOutcome chosen = setup.plan(search(3, 1));
  ASSERT_TRUE(chosen.feasible) << chosen.check.message;
  ASSERT_NE(chosen.visits.visit, planning::schedule_missions(pb, 40).visit);
  const std::string path = scratch("plan.json").string();
  planning::write_plan_json(path, pb, chosen);
  const planning::MissionSchedule back = planning::read_plan_visits(path, pb, 40);
  EXPECT_EQ(back.visit, chosen.visits.visit);
  EXPECT_EQ(back.horizon, 40);

  nlohmann::json j;
  std::ifstream(path) >> j;
  j["agents"][0]["visits"][0]["step"] = 40;  // no room left for the goal at T
  const std::string bad = scratch("bad.json").string();
  std::ofstream(bad) << j.dump();
  try {
    planning::read_plan_visits(bad, pb, 40);
    ADD_FAILURE() << "a knot at T was read";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("visits"), std::string::npos) << e.what();
  }
  j["agents"][0].erase("visits");
  const std::string old = scratch("old.json").string();
  std::ofstream(old) << j.dump();
  EXPECT_EQ(planning::read_plan_visits(old, pb, 40).visit, planning::schedule_missions(pb, 40).visit);
  std::filesystem::remove_all(std::filesystem::path(path).parent_path());
}

// A planner chain: the first planner's knots start the main planner with its plan (corridor.yaml,
// altro warm-starting altro): the main planner's first attempt is at the knots the first one
// chose, not at the initial guess it already failed at.
TEST(MissionRetime, TheFirstPlannersKnotsStartTheMainPlanner) {
  LoadedProblem lp = load_problem(kCorridor);
  lp.problem.warm_start_planner = {"altro", {}};
  marsyn::Setup setup(std::move(lp));
  const planning::PlanOutcome o = setup.plan(search(3, 1));
  ASSERT_TRUE(o.feasible) << o.check.message;
  ASSERT_GE(o.attempts.size(), 3u);
  const auto initial = planning::schedule_missions(setup.problem(), 40).visit;
  EXPECT_EQ(o.attempts[0].visits.visit, initial);     // the first planner, at the initial guess
  EXPECT_NE(o.attempts[1].visits.visit, initial);     // re-timed, robust
  EXPECT_TRUE(o.attempts[1].check.passed);
  EXPECT_EQ(o.attempts[2].visits.visit, o.attempts[1].visits.visit);  // the main planner starts there
}

// After a robust plan, re-timing rounds lower the input effort; a round whose knots come back
// within a few steps of knots already solved for is an oscillation and is not solved
// (examples/rendezvous.yaml: 51, then 45, then 49 was three more solves, none kept). Its first
// solve is robust in continuous time (the clearance follows each robot's fastest leg).
TEST(MissionRetime, RoundsStopWhenTheKnotsComeBack) {
  marsyn::Setup setup(load_problem(std::string(MARSYN_SOURCE_DIR) + "/examples/rendezvous.yaml"));
  const planning::PlanOutcome o = setup.plan(search(3, 1));
  ASSERT_TRUE(o.feasible) << o.check.message;
  ASSERT_FALSE(o.attempts.empty());
  EXPECT_TRUE(o.attempts[0].check.passed) << o.attempts[0].check.message;
  EXPECT_TRUE(o.attempts[0].check.continuous);
  const int jitter = std::max(2, o.horizon / 40);
  for (std::size_t i = 0; i < o.attempts.size(); ++i)
    for (std::size_t j = 0; j < i; ++j) {
      const auto& a = o.attempts[i].visits.visit;
      const auto& b = o.attempts[j].visits.visit;
      if (a == b) continue;  // the same knots again: a retry with more clearance
      int shift = 0;
      for (std::size_t r = 0; r < a.size(); ++r)
        for (std::size_t s = 0; s < a[r].size(); ++s) shift = std::max(shift, std::abs(a[r][s] - b[r][s]));
      EXPECT_GE(shift, jitter) << "attempt " << i << " re-solves near attempt " << j << "'s knots";
    }
}

// drag_team.yaml: at T = 70 the planner gives up (robot a cannot cover its path in time). The
// first such attempt is re-timed along once (that is how the corridor above is solved); when the
// re-timed attempt is given up on too, the next attempt is at a longer horizon, not at knots
// re-timed along a plan that never was one (before: four attempts at T = 70, two at T = 88).
TEST(MissionRetime, AReTimedAttemptGivenUpOnEndsTheHorizon) {
  marsyn::Setup setup(load_problem(std::string(MARSYN_SOURCE_DIR) + "/tests/core/mission_retime/drag_team.yaml"));
  const planning::PlanOutcome o = setup.plan(search(3, 4));
  ASSERT_TRUE(o.feasible) << o.check.message;
  ASSERT_GE(o.attempts.size(), 2u);
  EXPECT_EQ(o.attempts[0].horizon, 70);
  int given_up_at_70 = 0;
  for (std::size_t i = 0; i < o.attempts.size(); ++i) {
    const planning::PlanAttempt& a = o.attempts[i];
    const bool given_up = a.status != PlannerStatus::ExactSolution && a.status != PlannerStatus::ApproximateSolution;
    given_up_at_70 += given_up && a.horizon == 70;
    if (given_up && a.retimed && i + 1 < o.attempts.size())
      EXPECT_GT(o.attempts[i + 1].horizon, a.horizon) << "attempt " << i + 1 << " re-timed along a plan given up on twice";
  }
  // Three: the first attempt presses a against the wedge, so its route comes first (issue 49),
  // then one re-timing along the routed plan; given up on, the horizon is longer.
  EXPECT_EQ(given_up_at_70, 3);
}
