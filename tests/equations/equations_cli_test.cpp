// Equation models as a user meets them: `marsyn check` accepts them, and every error class of
// issue 15 is one located line `error: FILE:LINE:COLUMN: PATH: message` with exit code 2, the
// column pointing into the expression where the error is.
#include <gtest/gtest.h>

#include "run.hpp"

using marsyn::test::run_marsyn;
using marsyn::test::write_temp;

namespace {

const std::string kValid = R"(name: eq
tau: 0.1
horizon: 20
defaults:
  dynamics:
    states: [x, y, theta]
    inputs: [v, omega]
    constants: {k: 1.0}
    field:
      x: v * cos(theta)
      y: v * sin(theta)
      theta: k * omega
    footprints:
      nose: [x + 0.3 * cos(theta), y + 0.3 * sin(theta)]
  state_bounds: {lo: [-1, -1, -2], hi: [11, 11, 3]}
  input_bounds: {lo: [-2, -2], hi: [2, 2]}
  disturbance: [0, 0.02, 0.02]
  eps: [0.2, 0.2, 0.24]
  eta_x: [0.025, 0.025, 0.03]
  eta_u: [0.3, 0.3]
  workspace: {position: [0, 1]}
agents:
  - name: a
    x0: [0, 2, 0]
    goal: {center: [5, 2, 0], radius: [0.3, 0.3, 0.4]}
  - name: b
    dynamics: {params: {k: 0.5}}
    x0: [0, 6, 0]
    goal: {center: [5, 6, 0], radius: [0.3, 0.3, 0.4]}
    workspace: {footprint: nose}
)";

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "fixture does not contain: " << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

// 1-based line and column of the first occurrence of `needle` (at its `offset`-th character).
std::pair<int, int> where(const std::string& text, const std::string& needle, std::size_t offset = 0) {
  const auto pos = text.find(needle);
  EXPECT_NE(pos, std::string::npos) << needle;
  const auto at = pos + offset;
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
  const auto line_start = text.rfind('\n', at - 1);
  const int col = static_cast<int>(at - (line_start == std::string::npos ? 0 : line_start + 1)) + 1;
  return {line, col};
}

void expect_error(const std::string& name, const std::string& yaml, std::pair<int, int> at, const std::string& path,
                  const std::string& message) {
  const std::string file = write_temp(name + ".yaml", yaml);
  const auto r = run_marsyn("check " + file);
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  const std::string want = "error: " + file + ":" + std::to_string(at.first) + ":" + std::to_string(at.second) + ": " +
                           path + ": ";
  EXPECT_EQ(r.err.rfind(want, 0), 0u) << "expected the prefix " << want << "\ngot: " << r.err;
  EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "exactly one message: " << r.err;
}

}  // namespace

TEST(EquationsCli, ValidFileIsAcceptedWithAStableType) {
  const std::string file = write_temp("eq_valid.yaml", kValid);
  const auto r = run_marsyn("check " + file);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("equations:"), std::string::npos) << r.out;
  // The two agents differ in k: two different model types; the same file gives the same types.
  const auto again = run_marsyn("check " + file);
  EXPECT_EQ(r.out, again.out);
}

TEST(EquationsCli, ExamplesAreAccepted) {
  for (const char* example : {"unicycle_equations.yaml", "crane_vehicle_equations.yaml"}) {
    const auto r = run_marsyn(std::string("check ") + MARSYN_SOURCE_DIR + "/examples/" + example);
    EXPECT_EQ(r.code, 0) << example << ": " << r.err;
  }
}

TEST(EquationsCli, UnknownSymbolPointsAtTheName) {
  const std::string y = replace(kValid, "x: v * cos(theta)", "x: v * cos(thetta)");
  expect_error("eq_unknown", y, where(y, "thetta"), "defaults.dynamics.field.x",
               "unknown symbol 'thetta' (did you mean 'theta'?); states: x, y, theta; inputs: v, omega; constants: k; and pi");
}

TEST(EquationsCli, SyntaxErrorPointsAtTheColumn) {
  const std::string y = replace(kValid, "y: v * sin(theta)", "y: v * sin(theta))");
  expect_error("eq_syntax", y, where(y, "v * sin(theta))", 14), "defaults.dynamics.field.y",
               "syntax error at column 15 of the expression: unexpected ')'");
}

TEST(EquationsCli, QuotedAndBlockScalarsAreMappedToo) {
  const std::string q = replace(kValid, "y: v * sin(theta)", "y: \"v * sin(theta) +\"");
  expect_error("eq_quoted", q, where(q, "v * sin(theta) +\"", 16), "defaults.dynamics.field.y",
               "syntax error at column 17 of the expression: unexpected end");
  const std::string b = replace(kValid, "      y: v * sin(theta)\n", "      y: |\n        v *\n          sin(thetaa)\n");
  expect_error("eq_block", b, where(b, "thetaa"), "defaults.dynamics.field.y", "unknown symbol 'thetaa'");
}

TEST(EquationsCli, StateWithoutEquation) {
  const std::string y = replace(kValid, "      theta: k * omega\n", "");
  expect_error("eq_missing", y, where(y, "x: v * cos"), "defaults.dynamics.field", "the state 'theta' has no equation");
}

TEST(EquationsCli, EquationForSomethingElseThanAState) {
  const std::string y = replace(kValid, "      theta: k * omega\n", "      theta: k * omega\n      omega: 1\n");
  expect_error("eq_not_state", y, where(y, "omega: 1"), "defaults.dynamics.field.omega",
               "'omega' is not a state; the field gives one equation per state (states: x, y, theta)");
}

TEST(EquationsCli, DefinitionsAreCheckedAndUsable) {
  const std::string ok = replace(kValid, "    field:\n      x: v * cos(theta)", "    definitions: {c: cos(theta)}\n    field:\n      x: v * c");
  const auto r = run_marsyn("check " + write_temp("eq_def_ok.yaml", ok));
  EXPECT_EQ(r.code, 0) << r.err;
  const std::string bad = replace(kValid, "    field:\n", "    definitions: {c: cos(tehta)}\n    field:\n");
  expect_error("eq_def_bad", bad, where(bad, "tehta"), "defaults.dynamics.definitions.c", "unknown symbol 'tehta'");
}

TEST(EquationsCli, NameUsedTwice) {
  const std::string y = replace(kValid, "inputs: [v, omega]", "inputs: [v, x]");
  expect_error("eq_twice", y, where(y, "x]"), "defaults.dynamics.inputs[1]", "the name 'x' is used twice (also a state)");
}

TEST(EquationsCli, UnsupportedFunction) {
  const std::string y = replace(kValid, "theta: k * omega", "theta: k * abs(omega)");
  expect_error("eq_function", y, where(y, "abs("), "defaults.dynamics.field.theta",
               "unsupported function 'abs' (supported: sin, cos, tan, exp, log, sqrt, atan)");
}

TEST(EquationsCli, NonFiniteConstant) {
  const std::string y = replace(kValid, "constants: {k: 1.0}", "constants: {k: .inf}");
  expect_error("eq_inf", y, where(y, ".inf"), "defaults.dynamics.constants.k", "the constant 'k' is not finite");
  const std::string z = replace(kValid, "x: v * cos(theta)", "x: v * cos(theta) + 1e400");
  expect_error("eq_big", z, where(z, "1e400"), "defaults.dynamics.field.x", "outside the range of finite doubles");
}

// Constants: `constants` in the model, then its own `params`, then an agent's `params`; the
// model type names the values, so three different values give three types.
TEST(EquationsCli, PerAgentConstantsOverrideInOrder) {
  std::string y = replace(kValid, "    constants: {k: 1.0}\n", "    constants: {k: 1.0}\n    params: {k: 2.0}\n");
  y = replace(y, "  - name: a\n", "  - name: c\n    x0: [0, 8, 0]\n    goal: {center: [5, 8, 0], radius: [0.3, 0.3, 0.4]}\n    dynamics: {params: {k: 2.0}}\n  - name: a\n");
  const auto r = run_marsyn("check " + write_temp("eq_params_order.yaml", y));
  ASSERT_EQ(r.code, 0) << r.err;
  auto type_of = [&](const std::string& agent) {
    const auto at = r.out.find("\n" + agent + " ");
    EXPECT_NE(at, std::string::npos) << r.out;
    const auto t = r.out.find("equations:", at);
    return r.out.substr(t, 18);
  };
  EXPECT_EQ(type_of("a"), type_of("c")) << r.out;  // k = 2 from the model's params, and from c's
  EXPECT_NE(type_of("a"), type_of("b")) << r.out;  // b sets k = 0.5
}

TEST(EquationsCli, PerAgentConstantsAreChecked) {
  const std::string y = replace(kValid, "{params: {k: 0.5}}", "{params: {kk: 0.5}}");
  expect_error("eq_param", y, where(y, "kk"), "agents[1].dynamics.params.kk", "unknown constant 'kk' (did you mean 'k'?)");
  const std::string z = replace(kValid, "{params: {k: 0.5}}", "{params: {k: .nan}}");
  expect_error("eq_param_nan", z, where(z, ".nan"), "agents[1].dynamics.params.k", "the constant 'k' is not finite");
}

TEST(EquationsCli, FootprintsAreStateFunctionsAndNamed) {
  const std::string y = replace(kValid, "y + 0.3 * sin(theta)]", "y + 0.3 * v]");
  expect_error("eq_fp_input", y, where(y, "y + 0.3 * v]"), "defaults.dynamics.footprints.nose[1]",
               "a footprint is a function of the state only; this coordinate reads the input 'v'");
  const std::string z = replace(kValid, "{footprint: nose}", "{footprint: tail}");
  expect_error("eq_fp_name", z, where(z, "tail"), "agents[1].workspace.footprint", "has no footprint 'tail'; it has: nose");
}

namespace {

// Two drones (the multi-drone settings on a smaller field), with `DYNAMICS` replaced.
const std::string kPair = R"(name: pair
tau: 0.1
horizon: 60
delta: 0.2
defaults:
  dynamics: DYNAMICS
  state_bounds: {lo: [-1, -1, -2], hi: [7, 6, 2]}
  input_bounds: {lo: [-2.4, -2.4], hi: [2.4, 2.4]}
  disturbance: [0, 0.02, 0.02]
  eps: [0.2, 0.2, 0.24]
  eta_x: [0.025, 0.025, 0.03]
  eta_u: [0.3, 0.3]
  workspace: {position: [0, 1]}
obstacles:
  - {name: block, box: {lo: [2.5, 2], hi: [3.5, 3]}}
agents:
  - {name: low, x0: [0, 1, 0], goal: {center: [5, 1, 0], radius: [0.3, 0.3, 0.4]}}
  - {name: high, x0: [0, 4, 0], goal: {center: [5, 4, 0], radius: [0.3, 0.3, 0.4]}}
)";

// A controller file without its dynamics type (a length-prefixed string after the header) and
// its trailing checksum, which covers that type.
std::string controller_body(const std::string& file, const std::string& type) {
  const std::string c = marsyn::test::slurp(file);
  const auto at = c.find(type);
  EXPECT_NE(at, std::string::npos) << file << " does not name " << type;
  if (at == std::string::npos || c.size() < at + type.size() + 8) return {};
  return c.substr(at + type.size(), c.size() - 8 - at - type.size());
}

}  // namespace

// The same plan and the same controller from the plugin and from its equations (the field is
// bit-identical, so every successor box is; the heading periodic in both, as the file records).
TEST(EquationsCli, SameControllerAsThePlugin) {
  const std::string plugin = write_temp("pair_plugin.yaml", replace(kPair, "DYNAMICS", "unicycle"));
  const std::string eq = write_temp(
      "pair_equations.yaml",
      replace(kPair, "DYNAMICS", "{states: [x, y, theta], inputs: [v, omega], periodic: [theta], field: {x: v * cos(theta), y: v * sin(theta), theta: omega}}"));
  const std::string out = write_temp("pair_out_dummy", "");
  const auto a = run_marsyn("track " + plugin + " --agent low --threads 1 --out " + out + "_plugin");
  ASSERT_EQ(a.code, 0) << a.err;
  const auto b = run_marsyn("track " + eq + " --agent low --threads 1 --out " + out + "_eq");
  ASSERT_EQ(b.code, 0) << b.err;
  const auto t = run_marsyn("check " + eq);
  const auto pos = t.out.find("equations:");
  ASSERT_NE(pos, std::string::npos) << t.out;
  const std::string type = t.out.substr(pos, t.out.find_first_of(" \n", pos) - pos);
  const std::string pa = controller_body(out + "_plugin/low.ctrl", "unicycle");
  const std::string pb = controller_body(out + "_eq/low.ctrl", type);
  EXPECT_GT(pa.size(), 1000u);
  EXPECT_TRUE(pa == pb) << "controllers differ (" << pa.size() << " vs " << pb.size() << " bytes)";
}

// The example solves end to end with equation models only, and `simulate` re-creates the same
// models from the file to replay the controllers.
TEST(EquationsCli, ExampleSolvesAndSimulates) {
  const std::string out = write_temp("eq_example_out_dummy", "") + "_dir";
  const std::string example = std::string(MARSYN_SOURCE_DIR) + "/examples/unicycle_equations.yaml";
  const auto r = run_marsyn("solve " + example + " --out " + out);
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("VERIFIED"), std::string::npos) << r.out;
  const auto s = run_marsyn("simulate " + example + " --controllers " + out + " --disturbance switching");
  EXPECT_EQ(s.code, 0) << s.out << s.err;
  EXPECT_NE(s.out.find("specification satisfied"), std::string::npos) << s.out;
}
