// `marsyn check` advises (issue 25 item 2, docs/parameters.md): every tracker's assessment per
// agent, auto's pick and its fallback order, and warnings with numbers on constructed cases.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "marsyn/core/planning/workspace_gaps.hpp"
#include "marsyn/core/problem/auto_tube.hpp"
#include "marsyn/core/problem/problem_advice.hpp"
#include "marsyn/core/problem/problem_summary.hpp"
#include "pendulum_variant.hpp"
#include "problem_variant.hpp"

namespace {

using marsyn::test::pendulum_variant;

std::string all(const marsyn::Advice& a) {
  std::string s;
  for (const auto& w : a.warnings) s += w + "\n";
  return s;
}

TEST(ProblemAdvice, TheExampleAsWrittenHasNoWarningAndEveryTrackerSpeaks) {
  const auto lp = marsyn::load_problem(pendulum_variant("advice_plain", "tracker: auto"));
  const marsyn::Advice a = marsyn::advise(lp);
  EXPECT_TRUE(a.warnings.empty()) << all(a);
  ASSERT_EQ(a.agents.size(), 1u);
  std::set<std::string> named;
  for (const auto& t : a.agents[0].trackers) named.insert(t.tracker);
  EXPECT_TRUE(named.count("abcd") && named.count("funnel") && named.count("never")) << marsyn::to_text(a);
  // auto picks the cheapest that accepts (the test tracker, at no cost) and falls back in order.
  EXPECT_TRUE(a.agents[0].automatic);
  EXPECT_EQ(a.agents[0].chosen, "never");
  ASSERT_EQ(a.agents[0].fallbacks.size(), 2u);
  const std::string text = marsyn::to_text(a);
  EXPECT_NE(text.find("  pendulum: never (auto's pick; fallback order: never, then " + a.agents[0].fallbacks[0] + ", then " +
                      a.agents[0].fallbacks[1] + ")"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("    abcd: accepts, about "), std::string::npos) << text;
}

TEST(ProblemAdvice, EpsBelowWhatTheDisturbanceForcesInOnePeriod) {
  // w tau = 0.01 x 0.1 = 0.001 in the rate; eps 0.0008 there.
  const auto lp = marsyn::load_problem(pendulum_variant(
      "advice_wtau", "tracker: never", {{"eps: [0.2, 0.2]", "eps: [0.2, 0.0008]"}, {"eta_x: [0.01, 0.01]", "eta_x: [0.01, 0.0005]"}}));
  const std::string w = all(marsyn::advise(lp));
  EXPECT_NE(w.find("pendulum: eps 0.0008 in 'rate' is at most what the disturbance alone moves the state in one period (w tau "
                   "= 0.01 x 0.1 = 0.001)"),
            std::string::npos)
      << w;
  // Just above: no warning.
  const auto ok = marsyn::load_problem(pendulum_variant(
      "advice_wtau_ok", "tracker: never", {{"eps: [0.2, 0.2]", "eps: [0.2, 0.0011]"}, {"eta_x: [0.01, 0.01]", "eta_x: [0.01, 0.0005]"}}));
  EXPECT_EQ(all(marsyn::advise(ok)).find("disturbance alone"), std::string::npos);
}

TEST(ProblemAdvice, EtaXAboveEps) {
  const auto lp =
      marsyn::load_problem(pendulum_variant("advice_eta", "tracker: never", {{"eta_x: [0.01, 0.01]", "eta_x: [0.3, 0.01]"}}));
  const std::string w = all(marsyn::advise(lp));
  EXPECT_NE(w.find("pendulum: eta_x 0.3 in 'angle' exceeds eps 0.2: no grid cell fits the tube"), std::string::npos) << w;
}

TEST(ProblemAdvice, AFallbackWhoseEstimateIsMinutes) {
  // auto picks the test tracker; abcd, its fallback, on a 0.0005 grid: 800 x 800 tube cells x 101
  // steps x 121 inputs x 1e-8 s = 78 s.
  const auto lp = marsyn::load_problem(pendulum_variant(
      "advice_slow", "tracker: auto",
      {{"eta_x: [0.01, 0.01]", "eta_x: [0.0005, 0.0005]"}, {"eta_u: [0.1]", "eta_u: [0.05]"}}));
  const std::string w = all(marsyn::advise(lp));
  EXPECT_NE(w.find("pendulum: the fallback abcd is estimated at 1."), std::string::npos) << w;
  EXPECT_NE(w.find(" min of one core"), std::string::npos) << w;
  EXPECT_NE(w.find("(it runs when "), std::string::npos) << w;
  // The file's grid: no such warning.
  EXPECT_EQ(all(marsyn::advise(marsyn::load_problem(pendulum_variant("advice_fast", "tracker: auto")))).find("estimated at"),
            std::string::npos);
}

TEST(ProblemAdvice, AFormationWhoseMuIsBelowWhatTheTubesCanChange) {
  std::ifstream in(std::string(MARSYN_SOURCE_DIR) + "/examples/formation.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  const std::string from = "eps: [0.12, 0.12, 0.24]";
  s.replace(s.find(from), from.size(), "eps: [0.24, 0.24, 0.24]");
  const std::string path = testing::TempDir() + "advice_formation.yaml";
  std::ofstream(path) << s;
  const std::string w = all(marsyn::advise(marsyn::load_problem(path)));
  EXPECT_NE(w.find("formation centre-north: mu 0.5 is not above sqrt(2) (eps_i + eps_j) = 0.6788"), std::string::npos) << w;
  EXPECT_NE(w.find("position eps below 0.1768 would do"), std::string::npos) << w;
  // The example as shipped (eps 0.12: 0.34 < 0.5): none.
  EXPECT_EQ(all(marsyn::advise(marsyn::load_problem(std::string(MARSYN_SOURCE_DIR) + "/examples/formation.yaml"))).find("formation"),
            std::string::npos);
}

}  // namespace

// Pairs that each give their own mu need no formation-wide one (docs/problem-format.md: "offsets
// and/or pairs"); `offsets` still do.
TEST(FormationFields, PairsWithTheirOwnMuNeedNoTopLevelMu) {
  std::ifstream in(std::string(MARSYN_SOURCE_DIR) + "/tests/bad_inputs/formation_pair_without_mu.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  const std::string from = "{agents: [b, a], lambda: 1.0}";
  s.replace(s.find(from), from.size(), "{agents: [b, a], lambda: 1.2, mu: 0.4}");
  const std::string path = testing::TempDir() + "formation_own_mu.yaml";
  std::ofstream(path) << s;
  const auto lp = marsyn::load_problem(path);
  ASSERT_EQ(lp.problem.formation.size(), 2u);
  EXPECT_DOUBLE_EQ(lp.problem.formation[0].mu, 0.3);
  EXPECT_DOUBLE_EQ(lp.problem.formation[1].mu, 0.4);
  EXPECT_DOUBLE_EQ(lp.problem.formation[1].lambda, 1.2);
  // Offsets without a formation-wide mu: refused, naming the field.
  const std::string bad = testing::TempDir() + "formation_offsets_no_mu.yaml";
  std::string t = text.str();
  t.replace(t.find("  pairs:"), std::string::npos, "  offsets: {a: [0, 0], b: [0, 1]}\n");
  std::ofstream(bad) << t;
  try {
    marsyn::load_problem(bad);
    ADD_FAILURE() << "offsets without mu accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("missing required field 'mu'"), std::string::npos) << e.what();
  }
}

namespace {

std::string formation_with_starts(const std::string& tag, const std::string& b_start, const std::string& mu) {
  std::ifstream in(std::string(MARSYN_SOURCE_DIR) + "/tests/bad_inputs/formation_pair_without_mu.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  s.replace(s.find("x0: [0, 1, 0]"), 13, "x0: " + b_start);
  s.replace(s.find("{agents: [b, a], lambda: 1.0}"), 29, "{agents: [b, a], lambda: 1.0, mu: " + mu + "}");
  const std::string path = testing::TempDir() + "formation_start_" + tag + ".yaml";
  std::ofstream(path) << s;
  return path;
}

}  // namespace

// A start outside a formation's lambda +- mu breaks the specification at t = 0: refused, naming
// both agents and the band (issue 51: "starts that break a formation's robust tolerance pass
// check silently"). One inside the band but not with the tubes around the starts: `check` warns
// and the plan stage says so at once.
TEST(FormationFields, StartsOutsideTheFormationAreNamed) {
  try {
    marsyn::load_problem(formation_with_starts("outside", "[0, 1.5, 0]", "0.3"));
    ADD_FAILURE() << "a start 1.5 apart passed a formation of 1 +- 0.3";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("x0 puts a and b 1.5 apart (Euclidean), outside their formation's lambda +- mu = [0.7, 1.3]"),
              std::string::npos)
        << e.what();
  }
  // 1.28 apart: inside 1 +- 0.3 by 0.02; the eps boxes (0.05 each) take sqrt(2) 0.1 = 0.14.
  const auto lp = marsyn::load_problem(formation_with_starts("tight", "[0, 1.28, 0]", "0.3"));
  const auto starts = marsyn::planning::crowded_starts(lp.problem);
  ASSERT_FALSE(starts.empty());
  const std::string said = marsyn::planning::describe(starts.front(), lp.problem);
  EXPECT_NE(said.find("a and b start 1.28 apart (Euclidean); their formation keeps 1 +- 0.3"), std::string::npos) << said;
  EXPECT_NE(said.find("no horizon can help; eps x 0.14 or less"), std::string::npos) << said;
  EXPECT_LT(marsyn::planning::start_eps_factor(lp.problem), 0.15);
  // Starting at lambda: nothing to say.
  EXPECT_TRUE(marsyn::planning::crowded_starts(marsyn::load_problem(formation_with_starts("fine", "[0, 1, 0]", "0.3")).problem).empty());
}

// A team of alike robots is one line in `check`'s table and one block in its advice (issue 54:
// a field of 1000 printed 4000 lines); an agent that differs, or an alike one after it, has its own.
TEST(ProblemAdvice, AlikeAgentsInARowShareOneLine) {
  std::ostringstream y;
  y << "name: alike\ntau: 0.1\nhorizon: 40\ndelta: 0.2\n"
       "defaults:\n  dynamics: unicycle\n  tracker: funnel\n"
       "  state_bounds: {lo: [-20, -20, -4], hi: [20, 20, 4]}\n  input_bounds: {lo: [-1, -2], hi: [1, 2]}\n"
       "  disturbance: [0.01, 0.01, 0.01]\n  eps: [0.2, 0.2, 0.3]\n"
       "agents:\n";
  for (int i = 1; i <= 6; ++i) {
    y << "  - name: u" << i << "\n    x0: [" << 2 * i << ", 0, 0]\n    goal: {center: [" << 2 * i
      << ", 3, 0], radius: [0.5, 0.5, 3.9]}\n";
    if (i == 5) y << "    eps: [0.25, 0.2, 0.3]\n";
  }
  const std::string path = testing::TempDir() + "alike.yaml";
  std::ofstream(path) << y.str();
  const auto lp = marsyn::load_problem(path);
  const std::string table = marsyn::summarize(lp.problem);
  EXPECT_NE(table.find("\nu1 .. u4 (4 agents)  unicycle"), std::string::npos) << table;
  EXPECT_NE(table.find("\nu5 "), std::string::npos) << table;
  EXPECT_NE(table.find("\nu6 "), std::string::npos) << table;
  EXPECT_EQ(table.find("\nu2 "), std::string::npos) << table;
  const std::string advice = marsyn::to_text(marsyn::advise(lp));
  EXPECT_NE(advice.find("  u1 .. u4 (4 agents): funnel (named in the file)"), std::string::npos) << advice;
  EXPECT_NE(advice.find("  u5: funnel"), std::string::npos) << advice;
  EXPECT_NE(advice.find("  u6: funnel"), std::string::npos) << advice;
  // A warning many agents share is one line naming them all (u5's eps in x differs).
  std::string strong = y.str();
  strong.replace(strong.find("disturbance: [0.01, 0.01, 0.01]"), 31, "disturbance: [2.5, 2.5, 0.01]");
  std::ofstream(path) << strong;
  const std::string warned = marsyn::to_text(marsyn::advise(marsyn::load_problem(path)));
  EXPECT_NE(warned.find("warning: u1 .. u4 (4 agents), u6: eps 0.2 in 'x'"), std::string::npos) << warned;
  EXPECT_NE(warned.find("warning: u1 .. u6 (6 agents): eps 0.2 in 'y'"), std::string::npos) << warned;
  EXPECT_NE(warned.find("warning: u5: eps 0.25 in 'x'"), std::string::npos) << warned;
  EXPECT_EQ(warned.find("warning: u2:"), std::string::npos) << warned;
}

// A robot whose auto eps would crowd its start against a kerb starts with a narrower tube, by
// its own factor; a robot with room keeps the first value (issue 51: one car beside a kerb,
// four cars' tubes narrowed, and a plan that failed at once before the search narrowed them).
TEST(ProblemAdvice, AnAutoEpsStartsRobustBesideAKerb) {
  const auto path = std::filesystem::temp_directory_path() / "marsyn_auto_eps_kerb.yaml";
  std::ofstream(path) << R"(name: kerb
tau: 0.1
horizon: 60
delta: 0.2
delta_norm: inf
defaults:
  dynamics: unicycle
  state_bounds: {lo: [-10, -10, -4], hi: [10, 10, 4]}
  input_bounds: {lo: [-2, -2], hi: [2, 2]}
  disturbance: [0.02, 0.02, 0.02]
  eps: auto
  workspace: {position: [x, y]}
obstacles:
  - {name: kerb, box: {lo: [-8, 1], hi: [8, 2]}}
agents:
  - {name: beside, x0: [-6, 0.5, 0], goal: {center: [6, -1, 0], radius: [1, 1, 0.6]}}
  - {name: free, x0: [-6, -5, 0], goal: {center: [6, -5, 0], radius: [1, 1, 0.6]}}
)";
  const auto lp = marsyn::load_problem(path.string());
  EXPECT_TRUE(marsyn::planning::crowded_starts(lp.problem).empty());
  const auto& beside = lp.problem.agents[0];
  const Eigen::VectorXd first = marsyn::first_auto_eps(beside, lp.problem.tau);
  EXPECT_EQ(lp.problem.agents[1].tube.eps, marsyn::first_auto_eps(lp.problem.agents[1], lp.problem.tau));
  // 0.3 from the kerb less delta 0.2 leaves 0.3: the first eps (0.5 in y) would crowd it.
  marsyn::Problem as_first = lp.problem;
  as_first.agents[0].tube.eps = first;
  const double f = marsyn::planning::start_eps_factors(as_first)[0];
  ASSERT_LT(f, 1.0);
  for (Eigen::Index k = 0; k < first.size(); ++k) EXPECT_NEAR(beside.tube.eps[k], 0.95 * f * first[k], 1e-12) << k;
  // A start exactly robust with the first value (0.8 from the kerb: delta 0.2 + eps 0.5 + 0.1
  // from x0 to the kerb's face... here 0.7 = delta + eps) keeps 5 % of room, not a margin of 0.
  const auto exact = marsyn::load_problem(
      marsyn::test::problem_variant(path.string(), {{"x0: [-6, 0.5, 0]", "x0: [-6, 0.3, 0]"}}, "auto_eps_kerb_exact"));
  ASSERT_LT(exact.problem.agents[0].tube.eps[1], first[1]);
  EXPECT_NEAR(exact.problem.agents[0].tube.eps[1], 0.95 * first[1], 1e-12);
  EXPECT_NE(lp.auto_tube[0].start_cap.find("where its start is crowded"), std::string::npos);
  EXPECT_TRUE(lp.auto_tube[1].start_cap.empty());
}
