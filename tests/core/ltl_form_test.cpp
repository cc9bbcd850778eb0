// The LTL form of missions (docs/tasks.md, "LTL form"): a formula over named regions loads to the
// same stages as the `stages:` list it stands for, and everything outside the fragment is a
// located error naming the operator and its column.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "marsyn/core/problem/config_error.hpp"
#include "marsyn/core/problem/problem_loader.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path kDir = fs::path(MARSYN_SOURCE_DIR) / "tests/core/ltl";

void expect_same_stages(const marsyn::Problem& yaml_form, const marsyn::Problem& ltl_form) {
  ASSERT_EQ(yaml_form.agents.size(), ltl_form.agents.size());
  for (std::size_t i = 0; i < yaml_form.agents.size(); ++i) {
    const auto& y = yaml_form.agents[i].stages;
    const auto& l = ltl_form.agents[i].stages;
    SCOPED_TRACE("agent " + yaml_form.agents[i].name);
    ASSERT_EQ(y.size(), l.size());
    for (std::size_t s = 0; s < y.size(); ++s) {
      SCOPED_TRACE("stage " + std::to_string(s));
      EXPECT_EQ(y[s].name, l[s].name);
      EXPECT_EQ(y[s].is_polygon(), l[s].is_polygon());
      ASSERT_EQ(y[s].polygon.size(), l[s].polygon.size());
      for (std::size_t v = 0; v < y[s].polygon.size(); ++v) EXPECT_EQ(y[s].polygon[v], l[s].polygon[v]);
      ASSERT_EQ(y[s].box.lo.size(), l[s].box.lo.size());
      ASSERT_EQ(y[s].box.hi.size(), l[s].box.hi.size());
      EXPECT_EQ(y[s].box.lo, l[s].box.lo);
      EXPECT_EQ(y[s].box.hi, l[s].box.hi);
      EXPECT_EQ(y[s].not_before, l[s].not_before);
      EXPECT_EQ(y[s].by, l[s].by);
      EXPECT_EQ(y[s].dwell, l[s].dwell);
      EXPECT_EQ(y[s].team, l[s].team);
    }
  }
}

std::string write(const std::string& stem, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("marsyn_ltl_" + std::to_string(::getpid()) + "_" + stem + ".yaml");
  std::ofstream(p) << text;
  return p.string();
}

// One unicycle, two regions, two obstacles; the formula goes on line 21.
std::string one_agent(const std::string& formula) {
  return "tau: 0.1\n"
         "horizon: 60\n"
         "delta: 0.2\n"
         "defaults:\n"
         "  dynamics: unicycle\n"
         "  state_bounds: {lo: [-1, -1, -2], hi: [11, 11, 3]}\n"
         "  input_bounds: {lo: [-2, -2], hi: [2, 2]}\n"
         "  disturbance: [0, 0.02, 0.02]\n"
         "  eps: [0.2, 0.2, 0.24]\n"
         "  eta_x: [0.025, 0.025, 0.03]\n"
         "  eta_u: [0.3, 0.3]\n"
         "  workspace: {position: [0, 1]}\n"
         "obstacles: [{name: wall, box: {lo: [5, 0], hi: [5.5, 4]}}, {name: pillar, box: {lo: [2, 6], hi: [3, 7]}}]\n"
         "regions:\n"
         "  pickup: {polygon: [[2, 2], [3, 2], [3, 3], [2, 3]]}\n"
         "  dropoff: {center: [8, 2, 0], radius: [0.5, 0.5, 1]}\n"
         "agents:\n"
         "  - name: a\n"
         "    x0: [1, 1, 0]\n"
         "    goal: {center: [8, 8, 0], radius: [0.3, 0.3, 0.4]}\n"
         "    ltl: '" + formula + "'\n";
}

TEST(LtlForm, LoadsToTheSameStagesAsTheYamlForm) {
  const auto y = marsyn::load_problem((kDir / "warehouse_stages.yaml").string());
  const auto l = marsyn::load_problem((kDir / "warehouse_ltl.yaml").string());
  ASSERT_EQ(y.problem.agents.size(), 4u);
  for (const auto& a : y.problem.agents) EXPECT_EQ(a.stages.size(), 2u) << a.name;
  expect_same_stages(y.problem, l.problem);
}

// `ltl` in defaults is every agent's mission unless the agent writes its own `stages` or `ltl`.
TEST(LtlForm, DefaultsGiveTheFormulaAndAnAgentsOwnMissionWins) {
  std::string text = one_agent("F(dropoff & F goal)");
  text.replace(text.find("  workspace:"), 0, "  ltl: F(pickup & F(dropoff & F goal)) & G !obstacles\n");
  text.erase(text.find("    ltl: '"));
  text += "  - name: b\n"
          "    x0: [1, 3, 0]\n"
          "    goal: {center: [8, 6, 0], radius: [0.3, 0.3, 0.4]}\n"
          "  - name: c\n"
          "    x0: [1, 5, 0]\n"
          "    goal: {center: [8, 4, 0], radius: [0.3, 0.3, 0.4]}\n"
          "    stages: [{name: dropoff, region: {center: [8, 2, 0], radius: [0.5, 0.5, 1]}}]\n";
  const auto lp = marsyn::load_problem(write("defaults", text));
  ASSERT_EQ(lp.problem.agents.size(), 3u);
  for (int i : {0, 1}) {
    const auto& st = lp.problem.agents[i].stages;
    ASSERT_EQ(st.size(), 2u);
    EXPECT_EQ(st[0].name, "pickup");
    EXPECT_TRUE(st[0].is_polygon());
    EXPECT_EQ(st[1].name, "dropoff");
    EXPECT_FALSE(st[1].is_polygon());
  }
  ASSERT_EQ(lp.problem.agents[2].stages.size(), 1u);
  EXPECT_EQ(lp.problem.agents[2].stages[0].name, "dropoff");
}

TEST(LtlForm, JustFGoalIsTheGoalAlone) {
  const auto lp = marsyn::load_problem(write("goal_alone", one_agent("F goal & G !wall")));
  EXPECT_TRUE(lp.problem.agents[0].stages.empty());
}

struct Bad {
  std::string formula, message;
  int column;
};

// Each formula outside the fragment: the error is at agents[0].ltl (line 21), names what is
// unsupported, and gives its column in the formula.
TEST(LtlForm, FormulasOutsideTheFragmentAreLocatedErrors) {
  const std::vector<Bad> cases = {
      {"F(pickup & F goal) | F goal", "unsupported operator '|' (disjunction)", 20},
      {"F(pickup || F goal)", "unsupported operator '||' (disjunction)", 10},
      {"pickup U goal", "unsupported operator 'U' (until)", 8},
      {"F(pickup & X F goal)", "unsupported operator 'X' (next)", 12},
      {"F goal & (wall R goal)", "unsupported operator 'R' (release)", 16},
      {"pickup W goal", "unsupported operator 'W' (weak until)", 8},
      {"pickup M goal", "unsupported operator 'M' (strong release)", 8},
      {"F(pickup -> F goal)", "unsupported operator '->' (implication)", 10},
      {"F(pickup <-> F goal)", "unsupported operator '<->' (equivalence)", 10},
      {"F goal & true", "unsupported constant 'true'", 10},
      {"F goal & G false", "unsupported constant 'false'", 12},
      {"[] !wall & F goal", "unsupported operator '[]'", 1},
      {"F goal ^ F pickup", "unsupported operator '^'", 8},
      {"F goal & G F pickup", "unsupported G over F", 12},
      {"F goal & G (!wall & !pillar)", "unsupported G over a conjunction (&)", 13},
      {"F goal & G pickup", "unsupported G over 'pickup'", 12},
      {"F goal & !wall", "unsupported '!' at the top level", 10},
      {"F(pickup & F goal) & F dropoff", "a second F chain (the first at column 1)", 22},
      {"F(pickup & dropoff & F goal)", "two regions at once ('pickup' & 'dropoff')", 12},
      {"F(F pickup & F goal)", "a second F under one F", 14},
      {"F(pickup & F(!wall & F goal))", "unsupported '!' inside an F", 14},
      {"F F goal", "unsupported F directly under an F", 3},
      {"F(goal & F pickup)", "'goal' before the end of the chain", 3},
      {"F(pickup & F dropoff)", "the chain of F ends in 'F dropoff', not 'F goal'", 14},
      {"G !wall", "missing 'F goal'", 1},
      {"pickup & F goal", "a bare name 'pickup' at the top level", 1},
      {"F(pikcup & F goal)", "unknown region 'pikcup' (did you mean 'pickup'?)", 3},
      {"F(pickup & F(pickup & F goal))", "region 'pickup' visited a second time (first at column 3)", 14},
      {"F(pickup & F goal", "expected ')' to close the '(' at column 2", 18},
      {"F(pickup & F goal))", "unexpected ')'", 19},
      {"F goal G !wall", "unexpected 'G'", 8},
      {"", "expected a name, F, G, ! or '(', got 'end of the formula'", 1},
      {"F goal & G !wal", "G !wal at column 13", -1},
      {"F goal & G !wal", "(did you mean 'wall'?)", -1},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.formula);
    const std::string path = write("bad", one_agent(c.formula));
    try {
      marsyn::load_problem(path);
      ADD_FAILURE() << "loaded";
    } catch (const marsyn::ConfigError& e) {
      EXPECT_EQ(e.path(), "agents[0].ltl");
      EXPECT_EQ(e.line(), 21);
      EXPECT_NE(e.message().find(c.message), std::string::npos) << e.message();
      if (c.column > 0)
        EXPECT_NE(e.message().find(" at column " + std::to_string(c.column) + " of the formula"), std::string::npos)
            << e.message();
    }
  }
}

TEST(LtlForm, StagesAndLtlInOneAgentIsAnError) {
  std::string text = one_agent("F(pickup & F goal)");
  text += "    stages: [{name: pickup, region: {polygon: [[2, 2], [3, 2], [3, 3], [2, 3]]}}]\n";
  try {
    marsyn::load_problem(write("both", text));
    ADD_FAILURE() << "loaded";
  } catch (const marsyn::ConfigError& e) {
    EXPECT_EQ(e.path(), "agents[0].ltl");
    EXPECT_NE(e.message().find("either as 'stages' or as 'ltl', not both"), std::string::npos) << e.message();
  }
}

TEST(LtlForm, ARegionNamedLikeAReservedWordIsAnError) {
  for (const std::string word : {"goal", "F", "obstacles", "true"}) {
    std::string text = one_agent("F goal");
    text.replace(text.find("  pickup:"), 9, "  " + word + ":");
    try {
      marsyn::load_problem(write("reserved", text));
      ADD_FAILURE() << "loaded with a region named " << word;
    } catch (const marsyn::ConfigError& e) {
      EXPECT_EQ(e.path(), "regions." + word);
      EXPECT_NE(e.message().find("'" + word + "' is a reserved word of the LTL form"), std::string::npos) << e.message();
    }
  }
}

// A shared region checked against an agent's eps names the agent and its formula.
TEST(LtlForm, ARegionTooSmallForTheAgentsEpsNamesTheAgent) {
  std::string text = one_agent("F(dropoff & F goal)");
  text.replace(text.find("radius: [0.5, 0.5, 1]"), 21, "radius: [0.1, 0.5, 1]");
  try {
    marsyn::load_problem(write("small", text));
    ADD_FAILURE() << "loaded";
  } catch (const marsyn::ConfigError& e) {
    EXPECT_EQ(e.path(), "regions.dropoff");
    EXPECT_NE(e.message().find("is empty"), std::string::npos) << e.message();
    EXPECT_NE(e.message().find("(for agent 'a', which visits it in agents[0].ltl)"), std::string::npos) << e.message();
  }
}

}  // namespace
