// Each failed agent its own lever, ranked by evidence and predicted time (search_rank.hpp,
// docs/search.md): a small miss widens the tube first, a tracker knob predicted slower than
// another tracker waits behind it, and picks for several agents merge into one round.
#include <gtest/gtest.h>

#include "marsyn/core/search_rank.hpp"
#include "marsyn/core/search_report.hpp"
#include "marsyn/core/report/result_json.hpp"
#include "marsyn/core/solve.hpp"

namespace {

using marsyn::TrackFailureKind;
using marsyn::search::Candidate;
using marsyn::search::Failure;
using marsyn::search::Lever;
using marsyn::search::LeverChoice;

Candidate cand(Lever l, double s, const std::string& knob = "") {
  Candidate c;
  c.lever = {l, knob};
  c.predicted_s = s;
  return c;
}

TEST(SearchRank, AKnobPredictedSlowerThanAnotherTrackerWaitsBehindIt) {
  // The 100-unicycle field: the funnel's substeps at twice 45 s, abcd at 1.5 s.
  const std::vector<Candidate> slow{cand(Lever::TrackerLever, 90, "more enclosure substeps"), cand(Lever::FallBack, 1.5),
                                    cand(Lever::EnlargeEps, 60)};
  EXPECT_EQ(marsyn::search::best_candidate(slow), 1);
  // A cheap knob stays first: the evidence's order stands where time does not speak against it.
  const std::vector<Candidate> cheap{cand(Lever::TrackerLever, 1, "stiffer feedback"), cand(Lever::FallBack, 1.5)};
  EXPECT_EQ(marsyn::search::best_candidate(cheap), 0);
  // Every knob slower than the fallback is passed over, not only the first.
  const std::vector<Candidate> two{cand(Lever::TrackerLever, 9, "a"), cand(Lever::TrackerLever, 5, "b"), cand(Lever::FallBack, 2)};
  EXPECT_EQ(marsyn::search::best_candidate(two), 2);
  // Without another tracker the knobs run in their order.
  const std::vector<Candidate> none{cand(Lever::TrackerLever, 90, "a"), cand(Lever::EnlargeEps, 10)};
  EXPECT_EQ(marsyn::search::best_candidate(none), 0);
  EXPECT_EQ(marsyn::search::best_candidate({}), -1);
}

TEST(SearchRank, ASmallMissWidensTheTubeFirst) {
  const std::vector<marsyn::TrackerLever> declared{{"tighter knob", {TrackFailureKind::TubeMiss}, 1.0}};
  Failure f{Failure::NoController, "no controller for a", {0}, {}};
  f.why = {{TrackFailureKind::TubeMiss, 1, 5, 0.002, 0.0}};
  f.nominal_saturation = {0};
  f.miss_share = {0.01};  // 1 % of eps
  const auto levers = marsyn::search::levers_for(f, declared);
  ASSERT_FALSE(levers.empty());
  EXPECT_EQ(levers.front(), (LeverChoice{Lever::WidenForMiss, ""}));
  // A large miss is not closed by widening: the tracker's own knobs come first, as before.
  f.miss_share = {0.3};
  EXPECT_EQ(marsyn::search::levers_for(f, declared).front(), (LeverChoice{Lever::TrackerLever, "tighter knob"}));
  EXPECT_FALSE(marsyn::search::small_miss(f, 0));
  f.miss_share = {marsyn::search::kSmallMiss};
  EXPECT_TRUE(marsyn::search::small_miss(f, 0));
  // The widening: twice the miss and 1 % of eps.
  EXPECT_DOUBLE_EQ(marsyn::search::widened_eps(0.2, 0.0012), 0.2 + 0.0024 + 0.002);
}

TEST(SearchRank, OneAgentsFailureIsItsOwn) {
  Failure f{Failure::NoController, "no controller for a b", {3, 7}, {}};
  f.why = {{TrackFailureKind::TubeMiss, 1, 5, 0.01, 0.0}, {TrackFailureKind::EmptyWinningSet, -1, 7, 0.0, 0.0}};
  f.nominal_saturation = {0.1, 0.2};
  f.miss_share = {0.04, 0};
  const Failure b = marsyn::search::agent_failure(f, 1);
  EXPECT_EQ(b.agents, std::vector<int>{7});
  ASSERT_EQ(b.why.size(), 1u);
  EXPECT_EQ(b.why[0].kind, TrackFailureKind::EmptyWinningSet);
  EXPECT_EQ(b.nominal_saturation, std::vector<double>{0.2});
  EXPECT_EQ(b.miss_share, std::vector<double>{0});
}

TEST(SearchRank, PicksMergeIntoOneRound) {
  marsyn::Problem pb;
  pb.agents.resize(3);
  for (int i = 0; i < 3; ++i) {
    pb.agents[i].name = "a" + std::to_string(i);
    pb.agents[i].tube.eps = Eigen::VectorXd::Constant(2, 0.2);
  }
  std::vector<marsyn::AgentTrackers> trackers(3);
  std::map<std::string, double> extra;
  std::vector<double> share{1, 1, 1};
  int min_horizon = 0;
  const marsyn::search::Team team{&pb, &trackers, &extra, &share, &min_horizon};
  // Agent 0: a wider tube (re-checked); agent 2: a knob (keeps the plan).
  marsyn::search::Proposal wide;
  wide.agents = pb.agents;
  wide.agents[0].tube.eps[1] = 0.25;
  wide.changed = {0};
  wide.changes = {{"a0", "eps", "(0.2,0.2)", "(0.2,0.25)"}};
  wide.replan = wide.recheck = true;
  marsyn::search::Proposal knob;
  knob.agents = pb.agents;
  knob.agents[2].tracker.params.set("knob", 1L);
  knob.changed = {2};
  knob.changes = {{"a2", "tracker params", "{}", "{knob: 1}"}};
  const auto m = marsyn::search::merge({wide, knob}, team);
  EXPECT_DOUBLE_EQ(m.agents[0].tube.eps[1], 0.25);
  EXPECT_EQ(m.agents[2].tracker.params.integer("knob", 0), 1);
  EXPECT_EQ(m.agents[1].tube.eps, pb.agents[1].tube.eps);
  EXPECT_EQ(m.changed, (std::vector<int>{0, 2}));
  EXPECT_EQ(m.changes.size(), 2u);
  EXPECT_TRUE(m.replan);
  EXPECT_TRUE(m.recheck);  // only wider tubes re-plan: the plan may stay
  // A pick that must re-plan (U tightened) takes the recheck away.
  marsyn::search::Proposal tight;
  tight.agents = pb.agents;
  tight.input_share = {1, 0.8, 1};
  tight.changed = {1};
  tight.replan = true;
  const auto m2 = marsyn::search::merge({wide, tight}, team);
  EXPECT_TRUE(m2.replan);
  EXPECT_FALSE(m2.recheck);
  EXPECT_DOUBLE_EQ(m2.input_share[1], 0.8);
  EXPECT_EQ(marsyn::search::merged_action({"x", "x"}, {"a0", "a2"}), "x");
  EXPECT_EQ(marsyn::search::merged_action({"x", "y"}, {"a0", "a2"}), "a0: x; a2: y");
}

}  // namespace

// The stop message's "tried" counts levers, not per-agent round texts: a round that gave a1 a
// wider tube and a2 a knob counts once for each.
TEST(SearchRank, TriedCountsEachLeverOfAPerAgentRound) {
  marsyn::SearchReport r;
  r.rounds.resize(4);
  r.rounds[1].action = "a1: widen; a2: knob";
  r.rounds[2].action = "knob";
  r.rounds[3].action = "a1: knob; a2: knob; a3: fall back";
  EXPECT_EQ(r.tried(), "tried: widen x1, knob x3, fall back x1");
}

// A lever whose words hold "; " inside brackets is one lever ("... (its coordinate and those at
// the edge x2, the plan re-checked) x2" split it in two).
TEST(SearchRank, TriedKeepsALeversBracketsWhole) {
  marsyn::SearchReport r;
  r.rounds.resize(3);
  r.rounds[1].action = "widen eps (its coordinate; the plan re-checked)";
  r.rounds[2].action = "a1: widen eps (its coordinate; the plan re-checked); a2: knob";
  EXPECT_EQ(r.tried(), "tried: widen eps (its coordinate; the plan re-checked) x2, knob x1");
}

// The auto line no longer says "the first value stood" after the search's levers changed eps.
TEST(SearchRank, TheAutoNoteSaysWhenTheLeversChangedEps) {
  marsyn::SolveOutcome o;
  o.problem.agents.resize(2);
  o.problem.agents[0].name = "d1";
  o.problem.agents[1].name = "d2";
  o.search.rounds.resize(3);
  o.search.rounds[1].changes = {{"d1", "eps", "(0.2)", "(0.16)"}, {"", "eps factor", "0.8", "0.5"}};
  o.search.rounds[2].changes = {{"d1", "eps", "(0.16)", "(0.128)"}};
  EXPECT_EQ(marsyn::auto_search_note(o, 0), "the search's levers changed it in 2 rounds (search: rounds)");
  EXPECT_EQ(marsyn::auto_search_note(o, 1), "the first value stood");
  o.auto_notes = {"round 2's controller kept ...", ""};
  EXPECT_EQ(marsyn::auto_search_note(o, 0), "round 2's controller kept ...");
  // A round the search rolled back (a narrower auto eps that failed) changed nothing that stands.
  o.auto_notes.clear();
  o.search.rounds[2].undone = true;
  EXPECT_EQ(marsyn::auto_search_note(o, 0), "the search's levers changed it in 1 round (search: rounds)");
  EXPECT_EQ(marsyn::result_json(o)["search"]["rounds"][2]["undone"], true);
}
