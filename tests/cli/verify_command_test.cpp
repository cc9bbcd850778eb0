// `marsyn verify`: the closed-loop runs alone on a solve folder. The broad phase and the
// all-pairs reference print the same margins to the last digit; bad input is exit code 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "run.hpp"

using marsyn::test::run_marsyn;

namespace {

const std::string kExample = std::string(MARSYN_SOURCE_DIR) + "/examples/unicycle_equations.yaml";

// The output without the lines that differ by design (which check, how long it took).
std::string figures(const std::string& out) {
  std::istringstream in(out);
  std::string line, kept;
  while (std::getline(in, line))
    if (line.rfind("check", 0) != 0 && line.rfind("time", 0) != 0) kept += line + "\n";
  return kept;
}

}  // namespace

TEST(VerifyCommand, BroadPhaseAndAllPairsPrintTheSameFigures) {
  const std::string dir = std::filesystem::temp_directory_path() / "marsyn_verify_command";
  std::filesystem::remove_all(dir);
  ASSERT_EQ(run_marsyn("solve " + kExample + " --runs 5 --out " + dir).code, 0);
  const auto fast = run_marsyn("verify " + kExample + " --controllers " + dir + " --runs 40");
  const auto slow = run_marsyn("verify " + kExample + " --controllers " + dir + " --runs 40 --all-pairs");
  ASSERT_EQ(fast.code, 0) << fast.err;
  ASSERT_EQ(slow.code, 0) << slow.err;
  EXPECT_NE(fast.out.find("40 closed-loop runs, 0 violations"), std::string::npos) << fast.out;
  EXPECT_NE(fast.out.find("runs/s"), std::string::npos) << fast.out;
  EXPECT_EQ(figures(fast.out), figures(slow.out));
}

TEST(VerifyCommand, WithoutControllersIsBadInput) {
  const auto r = run_marsyn("verify " + kExample + " --controllers /nonexistent");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("/nonexistent/plan.json: cannot read the plan file"), std::string::npos) << r.err;
}
