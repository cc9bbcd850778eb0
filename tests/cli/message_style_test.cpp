// The message style (docs/messages.md) held over what users read: `check` on every problem and
// bad input of the repository, and the logs and summaries of a solve that verifies and of one
// that is stopped. The rules themselves are tested first, so that a rule that stopped catching
// its fault fails here rather than letting the sweep pass.
#include "../support/message_style.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "run.hpp"

namespace fs = std::filesystem;
using marsyn::test::run_marsyn;
using marsyn::test::style_breaks;
using marsyn::test::style_report;

namespace {

const fs::path kSource = MARSYN_SOURCE_DIR;

bool breaks_rule(const std::string& line, const std::string& rule) {
  const auto b = style_breaks(line);
  return std::any_of(b.begin(), b.end(), [&](const auto& x) { return x.rule == rule; });
}

std::vector<fs::path> yaml_under(const fs::path& dir, bool recursive) {
  std::vector<fs::path> out;
  auto take = [&](const fs::path& p) {
    if (p.extension() == ".yaml") out.push_back(p);
  };
  if (recursive)
    for (const auto& e : fs::recursive_directory_iterator(dir)) take(e.path());
  else
    for (const auto& e : fs::directory_iterator(dir)) take(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

// Lines from earlier logs (issue 54) each rule was written against, and lines it must leave alone.
TEST(MessageStyle, EachRuleCatchesWhatItIsFor) {
  EXPECT_TRUE(breaks_rule("ipopt: upper bound of x9 violated", "product-index"));
  EXPECT_TRUE(breaks_rule("planner: ipopt status 2 after 40 iterations", "raw-status"));
  EXPECT_TRUE(breaks_rule("NLOPT_ROUNDOFF_LIMITED", "raw-status"));
  EXPECT_TRUE(breaks_rule("... eps x 0.75 or less (or starts further apart) would", "cut"));
  EXPECT_TRUE(breaks_rule("the gap (from the wall", "cut"));
  EXPECT_TRUE(breaks_rule("the edge x = 0.000000", "fixed-point"));
  EXPECT_TRUE(breaks_rule("[track] all agents in 0.670510 s", "fixed-point"));
  EXPECT_TRUE(breaks_rule("eps (0.148492, 0.148492, 0.25)", "digits"));
  EXPECT_TRUE(breaks_rule("crane at (6.12323e-17, 0.1)", "rounding"));
  EXPECT_TRUE(breaks_rule("T = 150: infeasible after 267 iterations; eps-robust in continuous time", "contradiction"));
  EXPECT_TRUE(breaks_rule("global ABCD   N_g = inf state-input pairs, >= inf bytes: skipped", "non-finite"));
  EXPECT_TRUE(breaks_rule("no enclosure of the flow between steps 100 and 101 (margin -inf)", "non-finite"));
  EXPECT_TRUE(breaks_rule("eps [0.2, nan, 0.24] from the rule", "non-finite"));
  EXPECT_FALSE(breaks_rule("x0 puts b at (0.15, 2.1), inf-norm distance 0.15 from a", "non-finite"));
  EXPECT_FALSE(breaks_rule("T = 150: infeasible after 267 iterations", "non-finite"));
  EXPECT_FALSE(breaks_rule("the vector field is not finite at x0 (0, 0): dv/dt = inf (a division by zero?)", "non-finite"));
  EXPECT_TRUE(breaks_rule("[  100.01 s] [plan] solving: violation 0.112345", "digits"));  // the clock is not judged, the rest is

  for (const std::string clean :
       {"agents[0].x0: x0 puts b at (0.15, 2.1), inf-norm distance 0.15 from a at (0, 2)",
        "at step 36 of 685, y can leave the eps-tube by 0.0002439 (enclosure half-width 0.1916 vs eps 0.2)",
        "T = 150: infeasible after 267 iterations; NOT eps-robust in continuous time: -0.95",
        "write this mission as 'stages' with 'avoid' or 'avoid_after'", "violation 7.033e-11, 16.0 MiB, 0.590 s",
        "[track 1/3] eastbound (funnel): controller", "equations:ee582538  6 x 2",
        "output /tmp/x/run.1234567/plan.json", "agent's x_0 cell", "[  100.01 s] [plan] solving: iteration 39, cost 105.9"})
    EXPECT_EQ(style_report(clean), "") << clean;
}

// Everything `check` says (tables, advice, warnings, located errors) about every problem file of
// the repository: the examples, the problems new users wrote and the bad-input suite.
TEST(MessageStyle, CheckReadsOnEveryProblemAndBadInput) {
  std::vector<fs::path> files = yaml_under(kSource / "examples", false);
  for (const auto& p : yaml_under(kSource / "tests/problems", true)) files.push_back(p);
  for (const auto& p : yaml_under(kSource / "tests/bad_inputs", false)) files.push_back(p);
  ASSERT_GT(files.size(), 100u);
  for (const auto& f : files) {
    const auto r = run_marsyn("check " + f.string());
    EXPECT_EQ(style_report(r.out + r.err), "") << f;
  }
}

// A solve that verifies (its log, summary and the stop-free path) and one the time limit stops in
// planning (the stop message, what was tried).
TEST(MessageStyle, SolveLogsRead) {
  const fs::path out = fs::temp_directory_path() / ("marsyn_style_" + std::to_string(::getpid()));
  const auto ok =
      run_marsyn("solve " + (kSource / "examples/formation.yaml").string() + " --out " + (out / "ok").string());
  EXPECT_EQ(ok.code, 0) << ok.err;
  EXPECT_EQ(style_report(ok.out + ok.err), "");
  const auto stopped =
      run_marsyn("solve " + (kSource / "tests/problems/users2/04_eq_baggage_tugs_trailers.yaml").string() +
                 " --time-limit 6 --out " + (out / "stopped").string());
  EXPECT_NE(stopped.code, 0);
  EXPECT_NE(stopped.out.find("search"), std::string::npos) << stopped.out;
  EXPECT_EQ(style_report(stopped.out + stopped.err), "");
  fs::remove_all(out);
}
