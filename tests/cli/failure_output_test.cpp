// The output rule on failure (docs/problem-format.md, "Output files"): a solve that fails (exit
// 1) leaves result.json (status "failed", the reason, "partial") and report.html in the output
// folder, plan.json when it found an eps-robust plan, and the controllers it found (none here);
// controllers and plan.json from an earlier run of the problem are removed, files that are not
// marsyn's are left alone, and no staging folder remains.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "run.hpp"

namespace fs = std::filesystem;
using marsyn::test::run_marsyn;
using marsyn::test::slurp;
using marsyn::test::write_temp;

namespace {

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "fixture does not contain: " << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

std::set<std::string> entries(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.insert(e.path().filename().string());
  return out;
}

void expect_failure_output(const std::string& name, const std::string& yaml, const std::string& reason, bool planned) {
  const fs::path out = fs::temp_directory_path() / ("marsyn_fail_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(out);
  fs::create_directories(out);
  // Debris of an earlier, successful run, and a file of the user's.
  std::ofstream(out / "pendulum.ctrl") << "old";
  std::ofstream(out / "plan.json") << "{}";
  std::ofstream(out / "notes.txt") << "mine";
  const auto r = run_marsyn("solve " + write_temp(name + ".yaml", yaml) + " --out " + out.string() + " --runs 5");
  EXPECT_EQ(r.code, 1) << r.err;
  std::set<std::string> expected{"result.json", "report.html", "notes.txt"};
  if (planned) expected.insert("plan.json");
  EXPECT_EQ(entries(out), expected);
  if (planned) EXPECT_NE(slurp((out / "plan.json").string()), "{}") << "the plan of this run, not the old one";
  const std::string result = slurp((out / "result.json").string());
  EXPECT_NE(result.find("\"status\": \"failed\""), std::string::npos) << result.substr(0, 300);
  EXPECT_NE(result.find("\"failure\": \"" + reason), std::string::npos) << result.substr(0, 300);
  EXPECT_NE(result.find("\"partial\": false"), std::string::npos) << "no controller was found";
  EXPECT_EQ(result.find("\"controller\": \""), std::string::npos) << "no controller file is named";
  // The page embeds the result: its badge reads FAILED and the reason is in the page.
  const std::string page = slurp((out / "report.html").string());
  EXPECT_NE(page.find(reason), std::string::npos);
  EXPECT_NE(page.find("FAILED"), std::string::npos);
  EXPECT_EQ(slurp((out / "notes.txt").string()), "mine");
  EXPECT_NE(r.out.find("output        " + out.string() + (planned ? "/{plan.json, result.json, report.html}" : "/{result.json, report.html}")),
            std::string::npos)
      << r.out;
  fs::remove_all(out);
}

const std::string kPendulum = slurp(std::string(MARSYN_SOURCE_DIR) + "/examples/pendulum.yaml");

TEST(FailureOutput, PlanningFailure) {
  // |u| <= 0.01 cannot swing the pendulum up: no horizon gives a plan (fails in well under a second).
  expect_failure_output("plan_fails", replace(kPendulum, "input_bounds: {lo: [-3], hi: [3]}", "input_bounds: {lo: [-0.01], hi: [0.01]}"),
                        "planning failed", false);
}

TEST(FailureOutput, TrackingFailure) {
  // A disturbance of 3 on the velocity: the plan exists, no tracking controller does.
  std::string yaml = replace(kPendulum, "disturbance: [0, 0.01]", "disturbance: [0, 3]");
  yaml = replace(yaml, "eta_x: [0.01, 0.01]", "eta_x: [0.05, 0.05]");
  expect_failure_output("track_fails", yaml, "no controller for pendulum", true);
}

}  // namespace
