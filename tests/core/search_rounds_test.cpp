// What a round of the outer search keeps and where it starts (docs/search.md): agents whose
// nominal and parameters did not change keep their controllers, U is tightened per agent from
// the mild level, and a re-plan after a tracker failure starts from the plan it replaces. The
// test tracker `never` (tests/fixtures/never_tracker.cpp) fails on command by agent name.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/search_levers.hpp"
#include "marsyn/core/solve.hpp"
#include "pendulum_variant.hpp"
#include "quick_solve.hpp"

namespace {

using marsyn::test::pendulum_variant;

marsyn::SolveOptions quick(std::vector<std::string>* log = nullptr) { return marsyn::test::quick_solve(log); }

long count(const marsyn::SolveOutcome& o, const std::string& stage) {
  return std::count_if(o.attempts.begin(), o.attempts.end(), [&](const auto& a) { return a.stage == stage; });
}

// Two pendulums: `pendulum` (funnel, verifies) and `miss_pendulum` (never: a tube miss).
std::string two_pendulums(const std::string& name) {
  const std::string miss =
      "  - name: miss_pendulum\n"
      "    tracker: never\n"
      "    dynamics: {type: pendulum, params: {input_gain: 0.2}}\n"
      "    x0: [0, 0]\n"
      "    goal: {center: [3.141592653589793, 0], radius: [0.3, 0.3]}\n"
      "    state_bounds: {lo: [-2.5, -3], hi: [4.5, 3]}\n"
      "    input_bounds: {lo: [-30], hi: [30]}\n"
      "    disturbance: [0, 0.01]\n"
      "    eps: [0.2, 0.15]\n"  // never's miss of 0.01 is 6.7 % of it: not a small miss, the knobs run
      "  - name: pendulum\n";
  return pendulum_variant(name, "tracker: funnel",
                          {{"horizon: 100\n", "horizon: 100\npairwise_collision: false\n"}, {"  - name: pendulum\n", miss}, {"input_bounds: {lo: [-3], hi: [3]}", "input_bounds: {lo: [-30], hi: [30]}"}});
}

TEST(SearchRounds, AgentsWhoseNominalAndParametersDidNotChangeKeepTheirControllers) {
  std::vector<std::string> log;
  // The loaded problem holds the plugin libraries, whose code the controllers run: it outlives o.
  const auto lp = marsyn::load_problem(two_pendulums("rounds_keep"));
  const marsyn::SolveOutcome o = marsyn::solve(lp, quick(&log));
  ASSERT_GE(o.search.rounds.size(), 2u);
  ASSERT_EQ(o.search.rounds[1].action, "the tracker's tighter knob");
  ASSERT_FALSE(o.search.rounds[1].planned);
  // Round 2 kept the plan: the funnel pendulum was tracked in round 1 only, until a re-plan.
  const int replans = static_cast<int>(std::count_if(o.search.rounds.begin(), o.search.rounds.end(),
                                                     [](const auto& r) { return r.planned; }));
  EXPECT_LE(count(o, "track pendulum"), replans);
  EXPECT_GE(count(o, "track miss_pendulum"), 2);
  ASSERT_EQ(o.agents.size(), 2u);
  EXPECT_TRUE(o.agents[1].track.controller) << o.agents[1].track.message;
  EXPECT_NE(std::find(log.begin(), log.end(),
                      "[track] 1 agent(s) keep their controllers (nominal and parameters unchanged); tracking 1"),
            log.end());
}

TEST(SearchRounds, UIsTightenedPerAgentFromTheMildLevel) {
  EXPECT_DOUBLE_EQ(marsyn::search::next_input_share(1.0), 0.8);
  EXPECT_DOUBLE_EQ(marsyn::search::next_input_share(0.8), 0.6);
  EXPECT_DOUBLE_EQ(marsyn::search::next_input_share(0.6), 0.6);  // no level left
  auto lp = marsyn::load_problem(two_pendulums("rounds_share"));
  std::map<std::string, double> extra;
  std::vector<double> share{0.8, 1.0};  // miss_pendulum was tightened once, pendulum never
  int min_horizon = 0;
  const marsyn::search::Team team{&lp.problem, &lp.trackers, &extra, &share, &min_horizon};
  marsyn::TrackerInstances instances(lp.registry);
  marsyn::search::Failure f{marsyn::search::Failure::NoController, "no controller for miss_pendulum pendulum", {0, 1}, {}};
  f.why = {{}, {}};
  f.nominal_saturation = {0.5, 0.5};
  const auto p = marsyn::search::propose({marsyn::search::Lever::TightenInput, ""}, f, team, instances,
                                         {lp.problem.horizon, lp.problem.tau, lp.memory_budget}, 1);
  ASSERT_TRUE(p.why_not.empty()) << p.why_not;
  EXPECT_DOUBLE_EQ(p.input_share[0], 0.6);
  EXPECT_DOUBLE_EQ(p.input_share[1], 0.8);  // a fresh agent starts at 80 %, not at the other's 60 %
  EXPECT_TRUE(p.replan);
}

TEST(SearchRounds, AReplanAfterATrackerFailureStartsFromThePreviousPlan) {
  std::vector<std::string> log;
  const auto lp = marsyn::load_problem(pendulum_variant(
      "rounds_warm", "tracker: never",
      {{"- name: pendulum", "- name: pinned_pendulum"}, {"input_bounds: {lo: [-3], hi: [3]}", "input_bounds: {lo: [-30], hi: [30]}"}}));
  const marsyn::SolveOutcome o = marsyn::solve(lp, quick(&log));
  ASSERT_GE(o.search.rounds.size(), 2u);
  ASSERT_TRUE(o.search.rounds[1].planned);
  const auto warm = std::find_if(log.begin(), log.end(), [](const std::string& l) {
    return l.rfind("[plan] warm start: the previous plan (T = ", 0) == 0;
  });
  ASSERT_NE(warm, log.end());
  // Announced after round 2's lever, before its plan; never in round 1.
  const auto round2 = std::find_if(log.begin(), log.end(), [](const std::string& l) { return l.rfind("[search] round 2:", 0) == 0; });
  EXPECT_LT(round2 - log.begin(), warm - log.begin());
}

}  // namespace

// The log and the summary print a change made alike to several agents once (50 agents whose eps
// shrank by 0.8 made one line of 50 entries); changes that differ, and team-wide ones, stay apart.
TEST(SearchRounds, ChangesMadeAlikeArePrintedOnce) {
  using marsyn::SearchChange;
  const std::vector<SearchChange> changes{{"a", "eps", "(0.2)", "(0.16)"},
                                          {"b", "eps", "(0.2)", "(0.16)"},
                                          {"c", "eps", "(0.3)", "(0.24)"},
                                          {"", "eps factor", "0.8", "0.5"},
                                          {"d", "eps", "(0.2)", "(0.16)"}};
  const auto four = marsyn::grouped(changes, 4);
  ASSERT_EQ(four.size(), 3u);
  EXPECT_EQ(four[0].agent, "a, b and d");
  EXPECT_EQ(four[0].to, "(0.16)");
  EXPECT_EQ(four[1].agent, "c");
  EXPECT_EQ(four[2].agent, "");
  EXPECT_EQ(four[2].what, "eps factor");

  std::vector<SearchChange> team;
  for (int i = 0; i < 6; ++i) team.push_back({"a" + std::to_string(i), "eps", "(0.2)", "(0.16)"});
  EXPECT_EQ(marsyn::grouped(team, 6).front().agent, "every agent");
  const auto some = marsyn::grouped(team, 7);
  ASSERT_EQ(some.size(), 1u);
  EXPECT_EQ(some[0].agent, "a0, a1, a2 and 3 more");
  EXPECT_EQ(marsyn::grouped({team[0]}, 1).front().agent, "a0");
}

namespace {

// `never` agents (tests/fixtures/never_tracker.cpp) in the pendulum example: the pendulum
// renamed to the first name, a copy of it for each further one, all with eps `eps`, the test
// tracker and no collisions between them.
std::string never_team(const std::string& name, const std::vector<std::string>& agents, const std::string& eps,
                       const std::string& goal_radius = "[0.3, 0.3]", const std::string& tracker = "tracker: never") {
  std::string more;
  for (std::size_t k = 1; k < agents.size(); ++k)
    more += "  - name: " + agents[k] + "\n"
            "    dynamics: {type: pendulum, params: {input_gain: 0.2}}\n"
            "    x0: [0, 0]\n"
            "    goal: {center: [3.141592653589793, 0], radius: " + goal_radius + "}\n"
            "    state_bounds: {lo: [-2.5, -3], hi: [4.5, 3]}\n"
            "    input_bounds: {lo: [-3], hi: [3]}\n"
            "    disturbance: [0, 0.01]\n"
            "    eps: " + eps + "\n";
  return pendulum_variant(name, tracker,
                          {{"horizon: 100\n", "horizon: 100\npairwise_collision: false\n"},
                           {"- name: pendulum\n", "- name: " + agents.front() + "\n"},
                           {"eps: [0.2, 0.2]\n", "eps: " + eps + "\n"},
                           {"radius: [0.3, 0.3]", "radius: " + goal_radius},
                           {"eta_u: [0.1]\n", "eta_u: [0.1]\n" + more}});
}

}  // namespace

// A miss of a few per cent of eps (never's miss* agents: 0.01 in coordinate 1, here 4 % of eps)
// widens that agent's tube in that coordinate at once, and the plan is kept when the exact check
// passes with the wider tube: no re-plan, no tracker knob. With the fixed order of e0e42b8 the
// tracker's knob ran first.
TEST(SearchRounds, ASmallMissIsClosedByAWiderTubeWithoutAReplan) {
  std::vector<std::string> log;
  // The goal leaves the rate free (radius 2): the plan does not end on the rate's edge of the
  // shrunk goal, so a wider tube in the rate keeps it eps-robust.
  const auto lp = marsyn::load_problem(never_team("rounds_small_miss", {"miss_pendulum"}, "[0.2, 0.25]", "[0.3, 2.0]"));
  const marsyn::SolveOutcome o = marsyn::solve(lp, quick(&log));
  ASSERT_GE(o.search.rounds.size(), 2u);
  const auto& r2 = o.search.rounds[1];
  EXPECT_EQ(r2.action, marsyn::search::lever_name({marsyn::search::Lever::WidenForMiss, ""}));
  std::string said;
  for (const auto& l : log)
    if (l.rfind("[search]", 0) == 0) said += l + "\n";
  EXPECT_FALSE(r2.planned) << "the plan stays eps-robust with a tube 0.0225 wider in the rate\n" << said;
  ASSERT_EQ(r2.changes.size(), 1u);
  EXPECT_EQ(r2.changes[0].agent, "miss_pendulum");
  EXPECT_EQ(r2.changes[0].what, "eps");
  EXPECT_EQ(r2.changes[0].to, "(0.2,0.2725)");
  EXPECT_NE(std::find_if(log.begin(), log.end(),
                         [](const std::string& l) { return l.rfind("[search] the plan is still eps-robust with the wider tube", 0) == 0; }),
            log.end());
}

// The coordinates at the tube's edge are widened with the missed one, by the same factor
// (0.2725 / 0.25 = 1.09): missedge's sets reached 0.96 of eps in the angle before the miss
// (within kSmallMiss of the edge), missnear's 0.94 (not). Before TrackFailure::tube_use only the
// missed coordinate was widened, and the next round found the miss in the other one.
TEST(SearchRounds, ASmallMissWidensTheCoordinatesAtTheEdgeWithIt) {
  const auto lp =
      marsyn::load_problem(never_team("rounds_small_miss_edge", {"missedge_pendulum", "missnear_pendulum"}, "[0.2, 0.25]", "[0.5, 2.0]"));
  std::vector<std::string> log;
  const marsyn::SolveOutcome o = marsyn::solve(lp, quick(&log));
  // Both agents' wider tubes in one exact check of the plan (each alone would cost one each).
  EXPECT_NE(std::find_if(log.begin(), log.end(),
                         [](const std::string& l) {
                           return l.rfind("[search] the plan is eps-robust with the wider tubes of 2 agents at once (missedge_pendulum, "
                                          "missnear_pendulum; smallest margin ", 0) == 0;
                         }),
            log.end());
  // Each agent's first wider tube (the plan's end may send one agent's to a later round).
  std::map<std::string, std::string> eps;
  for (const auto& r : o.search.rounds)
    for (const auto& c : r.changes)
      if (c.what == "eps" && c.from == "(0.2,0.25)") eps[c.agent] = c.to;
  EXPECT_EQ(eps["missedge_pendulum"], "(0.218,0.2725)") << o.search.message();
  EXPECT_EQ(eps["missnear_pendulum"], "(0.2,0.2725)") << o.search.message();
}

// The same miss with the goal's rate tolerance 0.3: the plan ends on the edge of the shrunk goal
// (0.05 in the rate), which the wider tube moves inwards: the check fails. The tracker's knob,
// which keeps the plan, runs first (next test); once it has not helped, the wider tube re-plans,
// from the plan it replaces.
TEST(SearchRounds, ASmallMissReplansWhenTheWiderTubeBreaksThePlan) {
  std::vector<std::string> log;
  const auto lp = marsyn::load_problem(never_team("rounds_small_miss_replan", {"miss_pendulum"}, "[0.2, 0.25]"));
  const marsyn::SolveOutcome o = marsyn::solve(lp, quick(&log));
  const std::string widen = marsyn::search::lever_name({marsyn::search::Lever::WidenForMiss, ""});
  const auto r = std::find_if(o.search.rounds.begin(), o.search.rounds.end(), [&](const auto& x) { return x.action == widen; });
  ASSERT_NE(r, o.search.rounds.end()) << o.search.message();
  EXPECT_TRUE(r->planned);
  const auto said = std::find_if(log.begin(), log.end(), [](const std::string& l) {
    return l.rfind("[search] the plan is not eps-robust with the wider tube (NOT eps-robust", 0) == 0;
  });
  ASSERT_NE(said, log.end());
  EXPECT_NE(said->find("goal rate of miss_pendulum"), std::string::npos) << *said;
  EXPECT_NE(std::find_if(log.begin(), log.end(), [](const std::string& l) { return l.rfind("[plan] warm start: the previous plan", 0) == 0; }),
            log.end());
}

// When a lever keeps the plan, the wider tube that would break it waits: the knob (never's
// "tighter knob", predicted at no cost) runs before a re-plan.
TEST(SearchRounds, AWiderTubeThatBreaksThePlanWaitsBehindALeverThatKeepsIt) {
  std::vector<std::string> log;
  const auto lp = marsyn::load_problem(never_team("rounds_small_miss_knob", {"miss_pendulum"}, "[0.2, 0.25]"));
  const marsyn::SolveOutcome o = marsyn::solve(lp, quick(&log));
  ASSERT_GE(o.search.rounds.size(), 2u);
  EXPECT_EQ(o.search.rounds[1].action, "the tracker's tighter knob");
  EXPECT_FALSE(o.search.rounds[1].planned);
  EXPECT_NE(std::find_if(log.begin(), log.end(),
                         [](const std::string& l) {
                           return l.rfind("[search] miss_pendulum: the plan is not eps-robust with the wider tube (", 0) == 0 &&
                                  l.find("the tracker's tighter knob first") != std::string::npos;
                         }),
            log.end());
}

// Two agents failing for different reasons each get their own lever in the same round: the
// small miss its wider tube, the empty winning set the tracker's "finer cells". With e0e42b8's
// rule (the first failed agent's reason decides for all) both got "tighter knob".
TEST(SearchRounds, TwoFailingAgentsWithDifferentBestLeversAreServedInOneRound) {
  const auto lp = marsyn::load_problem(never_team("rounds_two_levers", {"miss_a", "empty_b"}, "[0.2, 0.25]", "[0.3, 2.0]"));
  const marsyn::SolveOutcome o = marsyn::solve(lp, quick());
  ASSERT_GE(o.search.rounds.size(), 2u);
  const auto& r2 = o.search.rounds[1];
  bool widened_a = false, cells_b = false;
  for (const auto& c : r2.changes) {
    widened_a = widened_a || (c.agent == "miss_a" && c.what == "eps");
    cells_b = cells_b || (c.agent == "empty_b" && c.what == "tracker params" && c.to.find("cells: 1") != std::string::npos);
  }
  EXPECT_TRUE(widened_a) << r2.action;
  EXPECT_TRUE(cells_b) << r2.action;
  EXPECT_NE(r2.action.find("miss_a: "), std::string::npos) << r2.action;
  EXPECT_NE(r2.action.find("empty_b: the tracker's finer cells"), std::string::npos) << r2.action;
}

// A planner the file names that finds no plan at any horizon is not the end: the default planner
// once (Ipopt held to 2 iterations cannot swing the pendulum up; altro can). Off with
// search: {planner_fallback: false}.
TEST(SearchRounds, ANamedPlannerThatFailsGivesWayToTheDefaultOnce) {
  const std::string weak = "planner: {name: ipopt, params: {max_iterations: 2}}";
  const auto lp = marsyn::load_problem(pendulum_variant("rounds_planner", "tracker: funnel", {{"planner: altro", weak}}));
  const marsyn::SolveOutcome o = marsyn::solve(lp, quick());
  ASSERT_GE(o.search.rounds.size(), 2u);
  EXPECT_EQ(o.search.rounds[1].action, "plan with the default planner (altro)");
  ASSERT_EQ(o.search.rounds[1].changes.size(), 1u);
  EXPECT_EQ(o.search.rounds[1].changes[0].from, "ipopt");
  EXPECT_TRUE(o.verified) << o.failure;

  const auto off = marsyn::load_problem(pendulum_variant(
      "rounds_planner_off", "tracker: funnel", {{"planner: altro", weak}, {"horizon: 100\n", "horizon: 100\nsearch: {planner_fallback: false, time_limit: 20}\n"}}));
  const marsyn::SolveOutcome o2 = marsyn::solve(off, quick());
  for (const auto& r : o2.search.rounds) EXPECT_NE(r.action, "plan with the default planner (altro)");
}

// Twice wider and still missing (never misses whatever the tube): the third round turns the
// tracker's own knob, which keeps the plan, before a third widening (misses that move between
// coordinates as the tube widens do not close by widening alone).
TEST(SearchRounds, AMissThatTwoWiderTubesDidNotCloseTurnsTheKnobNext) {
  const auto lp = marsyn::load_problem(never_team("rounds_widen_twice", {"miss_pendulum"}, "[0.2, 0.25]", "[0.3, 2.0]"));
  const marsyn::SolveOutcome o = marsyn::solve(lp, quick());
  ASSERT_GE(o.search.rounds.size(), 4u) << o.search.message();
  const std::string widen = marsyn::search::lever_name({marsyn::search::Lever::WidenForMiss, ""});
  EXPECT_EQ(o.search.rounds[1].action, widen);
  EXPECT_EQ(o.search.rounds[2].action, widen);
  EXPECT_EQ(o.search.rounds[3].action, "the tracker's tighter knob");
  EXPECT_FALSE(o.search.rounds[3].planned);
}

// A tracker knob that did not help the agent (never's tighter knob: the miss stays 0.01 at step 5)
// is not followed by another knob (never's other knob for miss_knobs agents, predicted cheaper)
// while another tracker accepts the agent: tracker: auto falls back to abcd next, which verifies
// (solve.cpp, kKnobsBeforeFallback).
TEST(SearchRounds, AKnobThatDidNotHelpIsFollowedByAnotherTracker) {
  std::vector<std::string> log;
  marsyn::LoadedProblem lp =
      marsyn::load_problem(never_team("rounds_knob_then_fallback", {"miss_knobs"}, "[0.2, 0.25]", "[0.3, 0.3]", "tracker: auto"));
  ASSERT_EQ(lp.problem.agents[0].tracker.name, "never");
  lp.trackers[0].fallbacks = {{"abcd", {}}};
  const marsyn::SolveOutcome o = marsyn::solve(lp, quick(&log));
  ASSERT_GE(o.search.rounds.size(), 3u) << o.search.message();
  EXPECT_EQ(o.search.rounds[1].action, "the tracker's tighter knob") << o.search.message();
  EXPECT_EQ(o.search.rounds[2].action, marsyn::search::lever_name({marsyn::search::Lever::FallBack, ""})) << o.search.message();
  EXPECT_TRUE(o.verified) << o.failure;
}
