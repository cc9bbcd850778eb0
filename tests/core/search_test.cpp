// The outer search (docs/search.md) on the pendulum with the test tracker `never`
// (tests/fixtures/never_tracker.cpp: never a controller; agents named slow* take 0.5 s per
// track): its budget is time, it says why it stops and what it tried, its times add up, it never
// runs the same attempt twice, and every attempt carries its own horizon.
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "marsyn/core/problem/config_error.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/report/result_json.hpp"
#include "marsyn/core/search_levers.hpp"
#include "marsyn/core/solve.hpp"
#include "pendulum_variant.hpp"
#include "quick_solve.hpp"

namespace {

using marsyn::test::pendulum_variant;

marsyn::SolveOptions quick(std::vector<std::string>* log = nullptr) { return marsyn::test::quick_solve(log); }

TEST(Search, SaysWhyItStopsWhatItTriedAndWhatIsLeft) {
  const auto lp = marsyn::load_problem(pendulum_variant("search_stop", "tracker: never"));
  std::vector<std::string> log;
  const marsyn::SolveOutcome o = marsyn::solve(lp, quick(&log));
  EXPECT_FALSE(o.verified);
  // never has no refinement and is not `auto`: eps x 1.25 once (0.25 < the goal's 0.3), then a
  // wider tube would swallow the goal.
  const std::string m = o.search.message();
  EXPECT_EQ(m.rfind("stopped: no controller for pendulum; no lever left after 2 rounds and ", 0), 0u) << m;
  EXPECT_NE(m.find("; tried: enlarge eps by 1.25 and re-plan x1; not tried: "), std::string::npos) << m;
  EXPECT_NE(m.find("fall back to the next tracker (tracker: auto) (the file names the agents' trackers; only tracker: auto "
                   "falls back)"),
            std::string::npos)
      << m;
  // never declares no lever for a failure without a reason (Tracker::levers), so none is listed.
  EXPECT_EQ(m.find("the tracker's"), std::string::npos) << m;
  // ... and says which coordinate of which agent refused it, with the numbers.
  EXPECT_NE(m.find("enlarge eps by 1.25 and re-plan (a wider tube is refused: pendulum: eps[angle] 0.3125 empties the goal, "
                   "whose half-width there is 0.3)"),
            std::string::npos)
      << m;
  const auto j = marsyn::result_json(o)["search"];
  EXPECT_EQ(j["stop_message"], m);
  ASSERT_EQ(j["rounds"].size(), 2u);
  EXPECT_EQ(j["rounds"][0]["action"], "first attempt");
  EXPECT_EQ(j["rounds"][1]["action"], "enlarge eps by 1.25 and re-plan");
  EXPECT_EQ(j["rounds"][1]["reason"], "no controller for pendulum");
  ASSERT_EQ(j["rounds"][1]["changes"].size(), 1u);
  EXPECT_EQ(j["rounds"][1]["changes"][0]["agent"], "pendulum");
  EXPECT_EQ(j["rounds"][1]["changes"][0]["what"], "eps");
  EXPECT_EQ(j["rounds"][1]["changes"][0]["from"], "(0.2,0.2)");
  EXPECT_EQ(j["rounds"][1]["changes"][0]["to"], "(0.25,0.25)");
  // The log announces exactly the rounds that ran, and ends with the stop message.
  std::vector<std::string> search_lines;
  for (const auto& l : log)
    if (l.rfind("[search] ", 0) == 0) search_lines.push_back(l);
  // The wider tube is checked on the existing plan first; the plan ends on the goal's edge, so it
  // is not robust with it and the round re-plans.
  ASSERT_EQ(search_lines.size(), 3u);
  EXPECT_EQ(search_lines[0].rfind("[search] round 2: no controller for pendulum; enlarge eps", 0), 0u) << search_lines[0];
  EXPECT_EQ(search_lines[1].rfind("[search] the plan is not eps-robust with the wider tube (", 0), 0u) << search_lines[1];
  EXPECT_EQ(search_lines[2], "[search] " + m);
}

TEST(Search, TheTimeLimitIsRespected) {
  // Each round tracks for 0.5 s: after the first (about 0.55 s) the second does not fit in 0.9 s.
  const auto lp = marsyn::load_problem(
      pendulum_variant("search_time", "tracker: never", {{"- name: pendulum", "- name: slow_pendulum"}}));
  marsyn::SolveOptions so = quick();
  so.time_limit_s = 0.9;
  const marsyn::SolveOutcome o = marsyn::solve(lp, so);
  EXPECT_LE(o.total_time_s, 1.1 * so.time_limit_s);
  EXPECT_EQ(o.search.rounds.size(), 1u);
  // Said as what it is (a lever that does not fit the time left), naming the best lever and its
  // predicted time, not as a clock that ran out.
  EXPECT_NE(o.search.stop_reason.find("no lever left fits the time left of the limit (0.9 s): the best, enlarge eps by 1.25 and re-plan, "
                                      "would take about "),
            std::string::npos)
      << o.search.stop_reason;
  ASSERT_FALSE(o.search.not_tried.empty());
  EXPECT_EQ(o.search.not_tried.back().lever, "enlarge eps by 1.25 and re-plan");
  EXPECT_EQ(o.search.not_tried.back().why.rfind("would take about ", 0), 0u) << o.search.not_tried.back().why;
}

TEST(Search, TheTimeLimitComesFromTheFileAndIsChecked) {
  const auto lp = marsyn::load_problem(pendulum_variant("search_field", "tracker: never", {{"tau:", "search: {time_limit: 42}\ntau:"}}));
  ASSERT_TRUE(lp.search_time_limit_s.has_value());
  EXPECT_EQ(*lp.search_time_limit_s, 42);
  // Every front end (solve, bench, Python) starts from it (bench did not: issue 53).
  EXPECT_EQ(marsyn::solve_options_for(lp).time_limit_s, 42);
  const std::string bad = pendulum_variant("search_bad", "tracker: never", {{"tau:", "search: {time_limit: -1}\ntau:"}});
  std::ifstream in(bad);
  int line = 1;
  for (std::string l; std::getline(in, l) && l.rfind("search:", 0) != 0;) ++line;
  try {
    marsyn::load_problem(bad);
    ADD_FAILURE() << "a negative time limit was accepted";
  } catch (const marsyn::ConfigError& e) {
    EXPECT_EQ(std::string(e.what()),
              bad + ":" + std::to_string(line) + ":22: search.time_limit: expected a positive number, got -1");
  }
}

TEST(Search, ReportedTimesAddUpToTheWallTime) {
  const auto lp = marsyn::load_problem(
      pendulum_variant("search_times", "tracker: never", {{"- name: pendulum", "- name: slow_pendulum"}}));
  const marsyn::SolveOutcome o = marsyn::solve(lp, quick());
  ASSERT_EQ(o.search.rounds.size(), 2u);
  double rounds = 0, plan = 0, track = 0;
  for (const auto& r : o.search.rounds) {
    rounds += r.time_s;
    plan += r.plan_time_s;
    track += r.track_time_s;
    EXPECT_LE(r.plan_time_s + r.track_time_s + r.certify_time_s, r.time_s * 1.0001);
  }
  const double accounted = rounds + o.verification.time_s + o.global.time_s;
  EXPECT_NEAR(accounted, o.total_time_s, 0.05 * o.total_time_s);
  const auto j = marsyn::result_json(o);
  // plan.time_s and the tracking time are totals over both rounds (both planned and tracked).
  EXPECT_DOUBLE_EQ(j["plan"]["time_s"].get<double>(), plan);
  EXPECT_GT(j["plan"]["time_s"].get<double>(), j["plan"]["last_round_time_s"].get<double>());
  EXPECT_DOUBLE_EQ(j["tracking_time_s"].get<double>(), track);
  EXPECT_GE(track, 2 * 0.5);
}

TEST(Search, NeverTheSameAttemptTwice) {
  // eps x 0.8 then x 1.25 is the tube the first round had: the fingerprint says so, and the
  // search refuses a proposal whose fingerprint it has seen.
  auto lp = marsyn::load_problem(pendulum_variant("search_repeat", "tracker: never"));
  std::map<std::string, double> extra;
  std::vector<double> share(lp.problem.agents.size(), 1.0);
  int min_horizon = 0;
  const marsyn::search::Team team{&lp.problem, &lp.trackers, &extra, &share, &min_horizon};
  marsyn::TrackerInstances instances(lp.registry);
  const marsyn::AssessRequest ask{lp.problem.horizon, lp.problem.tau, lp.memory_budget};
  const std::string first = marsyn::search::fingerprint(lp.problem.agents, extra);
  marsyn::search::Failure plan_failed{marsyn::search::Failure::Plan, "planning failed", {}, {}};
  const auto shrink = marsyn::search::propose({marsyn::search::Lever::ShrinkEps, ""}, plan_failed, team, instances, ask);
  ASSERT_TRUE(shrink.why_not.empty()) << shrink.why_not;
  EXPECT_NE(marsyn::search::fingerprint(shrink.agents, shrink.extra), first);
  marsyn::search::apply(shrink, team);
  marsyn::search::Failure no_controller{marsyn::search::Failure::NoController, "no controller for pendulum", {0}, {}};
  const auto enlarge = marsyn::search::propose({marsyn::search::Lever::EnlargeEps, ""}, no_controller, team, instances, ask);
  ASSERT_TRUE(enlarge.why_not.empty()) << enlarge.why_not;
  EXPECT_EQ(marsyn::search::fingerprint(enlarge.agents, enlarge.extra), first);

  // In a whole search no two tracking attempts share their parameters.
  const marsyn::SolveOutcome o = marsyn::solve(marsyn::load_problem(pendulum_variant("search_repeat2", "tracker: never")), quick());
  std::set<std::string> seen;
  for (const auto& a : o.attempts)
    if (a.stage == "track pendulum") EXPECT_TRUE(seen.insert(a.parameters).second) << "repeated: " << a.parameters;
  EXPECT_GE(seen.size(), 2u);
}

TEST(Search, EveryAttemptCarriesItsOwnHorizon) {
  // A horizon too short for the swing-up: the planning stage lengthens it, attempt by attempt.
  const auto lp = marsyn::load_problem(pendulum_variant("search_horizon", "tracker: never", {{"horizon: 100", "horizon: 40"}}));
  marsyn::SolveOptions so = quick();
  so.max_rounds = 1;
  const marsyn::SolveOutcome o = marsyn::solve(lp, so);
  std::set<int> horizons;
  for (const auto& a : o.attempts) {
    if (a.stage == "plan") {
      horizons.insert(a.horizon);
      EXPECT_NE(a.parameters.find(" T=" + std::to_string(a.horizon) + " "), std::string::npos) << a.parameters;
    }
    if (a.stage == "track pendulum") EXPECT_EQ(a.horizon, o.plan.horizon);
  }
  EXPECT_GE(horizons.size(), 2u) << "the planning stage tried one horizon only";
  EXPECT_GT(o.plan.horizon, 40);
  const auto j = marsyn::result_json(o);
  EXPECT_EQ(j["search"]["rounds"][0]["horizon"], o.plan.horizon);
  std::set<int> in_json;
  for (const auto& a : j["attempts"])
    if (a["stage"] == "plan") in_json.insert(a["horizon"].get<int>());
  EXPECT_EQ(in_json, horizons);
}

}  // namespace

namespace {

// A report of a search that never tracked (planning failed) still names every agent: the
// report's header counts result.json's agents (it said "0 agents" for 3).
TEST(Search, AResultWithoutTrackingListsEveryAgent) {
  marsyn::SolveOutcome o;
  o.problem = marsyn::load_problem(std::string(MARSYN_SOURCE_DIR) + "/examples/multi_drone.yaml").problem;
  ASSERT_EQ(o.problem.agents.size(), 10u);
  const auto j = marsyn::result_json(o);
  ASSERT_EQ(j["agents"].size(), 10u);
  EXPECT_EQ(j["agents"][0]["name"], o.problem.agents[0].name);
  EXPECT_EQ(j["agents"][0]["tracker"]["status"], "not tracked");
  EXPECT_EQ(j["agents"][9]["controller"], nullptr);
}

}  // namespace
