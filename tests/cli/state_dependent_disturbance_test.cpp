// A disturbance that grows with speed (docs/problem-format.md, `disturbance: {base, per}`):
// examples/rovers_slip.yaml's rovers stand still 20 s to drill. With the slip they have (W small
// at rest) the funnel holds them and the adversarial runs, drawn in W(x, u), stay safe; with a
// constant W of the moving rover's slip the funnel cannot hold a standing unicycle (no input
// pushes it sideways), and only abcd's manoeuvring controllers remain.
#include <gtest/gtest.h>

#include <filesystem>

#include "run.hpp"

namespace fs = std::filesystem;
using marsyn::test::run_marsyn;
using marsyn::test::slurp;
using marsyn::test::write_temp;

namespace {

const std::string kExample = std::string(MARSYN_SOURCE_DIR) + "/examples/rovers_slip.yaml";
const std::string kSlip = "  disturbance: {base: [0.004, 0.004, 0.005], per: {v: [0.04, 0.04, 0.03]}}\n";

std::string with(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

TEST(StateDependentDisturbance, CheckSaysTheFormulaAndItsLargestValue) {
  const auto r = run_marsyn("check " + kExample);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("disturbance rover1: W = (0.004, 0.004, 0.005) + (0.04, 0.04, 0.03) |v|, at most (0.024, 0.024, 0.02)"),
            std::string::npos)
      << r.out;
}

TEST(StateDependentDisturbance, ARoverStandingStillIsHeldOnlyUnderTheSlipItHas) {
  const std::string funnel = with(slurp(kExample), "delta_norm: inf\n", "delta_norm: inf\ntracker: funnel\n");
  const fs::path out = fs::temp_directory_path() / ("marsyn_slip_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const auto r = run_marsyn("solve " + write_temp("rovers_slip_funnel.yaml", funnel) + " --runs 200 --time-limit 60 --out " +
                            out.string());
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("status        VERIFIED"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("0 violations"), std::string::npos) << r.out;
  const std::string result = slurp((out / "result.json").string());
  EXPECT_NE(result.find("\"w_per\": {\n        \"v\": [\n          0.04,"), std::string::npos) << result.substr(0, 3000);
  EXPECT_NE(result.find("\"w_base\": ["), std::string::npos);

  // --resume with another W: the controllers were made for the old one, so each agent is tracked
  // again (the plan is kept).
  const std::string less = with(funnel, kSlip, "  disturbance: {base: [0.003, 0.004, 0.005], per: {v: [0.04, 0.04, 0.03]}}\n");
  const auto resumed = run_marsyn("solve " + write_temp("rovers_slip_less.yaml", less) + " --resume " + out.string() +
                                  " --runs 50 --out " + out.string() + "_resumed");
  EXPECT_EQ(resumed.code, 0) << resumed.out << resumed.err;
  EXPECT_NE(resumed.err.find("rover1's controller was made for another initial set (x0_radius) or disturbance (W): tracked again"),
            std::string::npos)
      << resumed.err;
  fs::remove_all(out.string() + "_resumed");

  // The largest W everywhere: the funnel finds no controller for a rover at rest.
  const std::string constant = with(funnel, kSlip, "  disturbance: [0.024, 0.024, 0.02]\n");
  const auto c = run_marsyn("solve " + write_temp("rovers_constant_funnel.yaml", constant) + " --runs 50 --time-limit 20 --out " +
                            out.string() + "_constant");
  EXPECT_EQ(c.code, 1) << c.out << c.err;
  EXPECT_EQ(c.out.find("status        VERIFIED"), std::string::npos) << c.out;
  EXPECT_NE(c.err.find("(funnel): no controller"), std::string::npos) << c.err;
  fs::remove_all(out);
  fs::remove_all(out.string() + "_constant");
}

}  // namespace
