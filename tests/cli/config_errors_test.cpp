// Every kind of bad input the foundation issue lists must end with exit code 2 and one message
// naming the file, the line, the field path and what was expected: never a crash or an abort.
#include <gtest/gtest.h>

#include <regex>

#include "run.hpp"

using marsyn::test::run_marsyn;
using marsyn::test::write_temp;

namespace {

const std::string kValid = R"(name: two
tau: 0.1
horizon: 20
delta: 0.2
defaults:
  dynamics: unicycle
  state_bounds: {lo: [-1, -1, -2], hi: [11, 11, 3]}
  input_bounds: {lo: [-2, -2], hi: [2, 2]}
  disturbance: [0, 0.02, 0.02]
  eps: [0.2, 0.2, 0.24]
  eta_u: [0.3, 0.3]
  workspace: {position: [0, 1]}
agents:
  - name: a
    x0: [0, 2, 0]
    goal: {center: [5, 2, 0], radius: [0.3, 0.3, 0.4]}
    eta_x: [0.025, 0.025, 0.03]
  - name: b
    x0: [0, 6, 0]
    goal: {center: [5, 6, 0], radius: [0.3, 0.3, 0.4]}
    eta_x: [0.025, 0.025, 0.03]
)";

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "fixture does not contain: " << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

// Runs `marsyn check` on `yaml` and expects exit 2 with one "error: FILE:LINE:COL: PATH: ..." line.
void expect_error(const std::string& name, const std::string& yaml, const std::string& path,
                  const std::string& expected, int line) {
  const std::string file = write_temp(name + ".yaml", yaml);
  const auto r = run_marsyn("check " + file);
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_TRUE(r.out.empty()) << "no summary may be printed for a bad file: " << r.out;
  const std::string want_prefix = "error: " + file + ":" + std::to_string(line) + ":";
  EXPECT_EQ(r.err.rfind(want_prefix, 0), 0u) << r.err;
  if (!path.empty()) EXPECT_NE(r.err.find(": " + path + ": "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "exactly one message: " << r.err;
}

}  // namespace

TEST(ConfigErrors, ValidFixtureIsAccepted) {
  const auto r = run_marsyn("check " + write_temp("valid.yaml", kValid));
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST(ConfigErrors, YamlSyntaxError) {
  expect_error("syntax", replace(kValid, "  - name: b\n", "  - name: [b\n"), "", "YAML syntax error", 19);
}

TEST(ConfigErrors, MissingOrUnreadableFile) {
  const auto r = run_marsyn("check /nonexistent/problem.yaml");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("/nonexistent/problem.yaml"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("cannot read"), std::string::npos) << r.err;
}

TEST(ConfigErrors, MissingRequiredField) {
  expect_error("missing", replace(kValid, "tau: 0.1\n", ""), "", "missing required field 'tau'", 1);
}

TEST(ConfigErrors, MissingAgentFieldNamesTheAgent) {
  expect_error("missing_agent", replace(kValid, "    x0: [0, 6, 0]\n", ""), "agents[1]",
               "missing required field 'x0'", 18);
}

TEST(ConfigErrors, UnknownFieldSuggestsTheNearestName) {
  expect_error("typo", replace(kValid, "    x0: [0, 6, 0]\n", "    x0: [0, 6, 0]\n    eta_xx: [1, 1, 1]\n"),
               "agents[1].eta_xx", "unknown field 'eta_xx' (did you mean 'eta_x'?)", 20);
}

TEST(ConfigErrors, VectorLengthMustMatchTheModel) {
  expect_error("length", replace(kValid, "    eta_x: [0.025, 0.025, 0.03]\n", "    eta_x: [0.025, 0.025]\n"),
               "agents[0].eta_x", "expected 3 numbers (the dynamics 'unicycle' has 3 states), got 2", 17);
}

TEST(ConfigErrors, X0OutsideStateBounds) {
  expect_error("x0", replace(kValid, "x0: [0, 6, 0]", "x0: [0, 16, 0]"), "agents[1].x0[1]",
               "lies outside the state bounds [-1, 11]", 19);
}

TEST(ConfigErrors, X0TubeOutsideStateBounds) {
  expect_error("x0tube", replace(kValid, "x0: [0, 6, 0]", "x0: [-0.9, 6, 0]"), "agents[1].x0[0]",
               "the tube around x0 leaves the state bounds", 19);
}

TEST(ConfigErrors, X0CellOutsideTheTubeGrid) {
  // abcd named (appended: no line moves): x0's cell is abcd's rule, asked through its assessment.
  expect_error("grid", replace(kValid + "tracker: abcd\n", "    eta_x: [0.025, 0.025, 0.03]\n  - name: b", "    eta_x: [0.5, 0.025, 0.03]\n  - name: b"),
               "agents[0].eta_x[0]", "does not fit inside the tube", 17);
}

TEST(ConfigErrors, EtaMustBePositive) {
  expect_error("eta", replace(kValid, "eta_u: [0.3, 0.3]", "eta_u: [0.3, 0]"), "defaults.eta_u[1]",
               "expected a positive number", 11);
}

TEST(ConfigErrors, EpsMustBePositive) {
  expect_error("eps", replace(kValid, "eps: [0.2, 0.2, 0.24]", "eps: [0.2, -0.2, 0.24]"), "defaults.eps[1]",
               "expected a positive number", 10);
}

TEST(ConfigErrors, TauMustBePositive) {
  expect_error("tau", replace(kValid, "tau: 0.1", "tau: 0"), "tau", "expected a positive number", 2);
}

TEST(ConfigErrors, HorizonMustBeAPositiveInteger) {
  expect_error("horizon", replace(kValid, "horizon: 20", "horizon: -3"), "horizon", "expected a positive integer", 3);
  expect_error("horizon2", replace(kValid, "horizon: 20", "horizon: 2.5"), "horizon", "expected an integer", 3);
}

TEST(ConfigErrors, NonFiniteNumbers) {
  expect_error("nan", replace(kValid, "eps: [0.2, 0.2, 0.24]", "eps: [.nan, 0.2, 0.24]"), "defaults.eps[0]",
               "expected a finite number", 10);
  expect_error("inf", replace(kValid, "x0: [0, 2, 0]", "x0: [0, .inf, 0]"), "agents[0].x0[1]",
               "expected a finite number", 15);
}

TEST(ConfigErrors, GoalEmptyAfterShrinkingByEps) {
  expect_error("goal", replace(kValid, "goal: {center: [5, 6, 0], radius: [0.3, 0.3, 0.4]}",
                               "goal: {center: [5, 6, 0], radius: [0.3, 0.1, 0.4]}"),
               "agents[1].goal", "the goal shrunk by eps is empty in 'y'", 20);
}

TEST(ConfigErrors, UnknownPluginName) {
  expect_error("plugin", replace(kValid, "dynamics: unicycle", "dynamics: unicycel"), "defaults.dynamics",
               "unknown dynamics plugin 'unicycel' (did you mean 'unicycle'?); available:", 6);
}

TEST(ConfigErrors, UnknownPlannerName) {
  expect_error("planner", replace(kValid, "delta: 0.2\n", "delta: 0.2\nplanner: {name: sqp}\n"), "planner.name",
               "unknown planner plugin 'sqp'", 5);
}

TEST(ConfigErrors, UnknownCollisionProvider) {
#ifndef MARSYN_HAVE_FCL_PLUGIN
  GTEST_SKIP() << "the fcl plugin is not built";
#endif
  expect_error("collision", replace(kValid, "delta: 0.2\n", "delta: 0.2\ncollision: fcll\n"), "collision",
               "unknown distance plugin 'fcll' (did you mean 'fcl'?); available: fcl (or 'exact' for core's own "
               "geometry)",
               5);
}

TEST(ConfigErrors, CollisionObstaclesComeFromTheProblem) {
#ifndef MARSYN_HAVE_FCL_PLUGIN
  GTEST_SKIP() << "the fcl plugin is not built";
#endif
  expect_error("collision_params",
               replace(kValid, "delta: 0.2\n", "delta: 0.2\ncollision: {name: fcl, params: {polygons: [3, 0, 0, 1, 0, 0, 1]}}\n"),
               "collision.params.polygons", "set by marsyn from the problem's `obstacles`; remove it here", 5);
  expect_error("collision_exact", replace(kValid, "delta: 0.2\n", "delta: 0.2\ncollision: {name: exact, params: {a: 1}}\n"),
               "collision.params", "core's exact geometry takes no parameters", 5);
}

TEST(ConfigErrors, UnknownWarmStartPlanner) {
  expect_error("warm_start", replace(kValid, "delta: 0.2\n", "delta: 0.2\nplanner: {name: altro, warm_start: ipop}\n"),
               "planner.warm_start", "unknown planner plugin 'ipop' (did you mean 'ipopt'?)", 5);
}

TEST(ConfigErrors, UnknownPluginParameter) {
  expect_error("param",
               replace(kValid, "  - name: b\n", "  - name: b\n    dynamics: {type: pendulum, params: {gain: 2}}\n"),
               "agents[1].dynamics.params.gain", "unknown field 'gain'", 19);
}

TEST(ConfigErrors, PluginLibraryOfAnotherApiVersion) {
  expect_error("api", replace(kValid, "delta: 0.2\n", std::string("delta: 0.2\nplugin_paths: [") + OTHER_API_PLUGIN_DIR + "]\n"),
               "plugin_paths[0]", "was built against marsyn plugin API version 999, but this marsyn uses API version ", 5);
}

TEST(ConfigErrors, DuplicateAgentNames) {
  expect_error("dup", replace(kValid, "  - name: b\n", "  - name: a\n"), "agents[1].name",
               "duplicate agent name 'a' (also agents[0])", 18);
}

TEST(ConfigErrors, WrongTypeIsNamed) {
  expect_error("type", replace(kValid, "delta: 0.2", "delta: far"), "delta", "expected a number, got 'far'", 4);
}
