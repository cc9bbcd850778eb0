// Reporting slips a user saw (issue 25 item 5) and the search's changes said per agent (item 3):
// `check`'s agent table keeps its columns apart whatever the values, counts read "1 agent",
// "1 input", and `solve`'s summary says why the search stopped and what it changed, from -> to.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "one_unicycle.hpp"
#include "run.hpp"

using marsyn::test::run_marsyn;
using marsyn::test::write_temp;

namespace {

std::string pendulum_with(const std::string& from, const std::string& to) {
  std::ifstream in(std::string(MARSYN_SOURCE_DIR) + "/examples/pendulum.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  s.replace(s.find(from), from.size(), to);
  return s;
}

// A unicycle whose grid has long values: three of them filled the old fixed-width column.
const std::string kLongEta = marsyn::test::one_unicycle(
    "tracker: abcd", "a", "    eta_x: [0.0123456789, 0.0123456789, 0.0123456789]\n    eta_u: [0.3, 0.3]\n");

TEST(Reporting, CheckTableKeepsLongValuesOutOfTheTrackerColumn) {
  const std::string file = write_temp("long_eta.yaml", kLongEta);
  const auto r = run_marsyn("check " + file);
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream lines(r.out);
  std::string header, row;
  for (std::string l; std::getline(lines, l);) {
    if (l.rfind("agent ", 0) == 0) header = l;
    if (l.rfind("a ", 0) == 0) row = l;
  }
  ASSERT_FALSE(header.empty()) << r.out;
  ASSERT_FALSE(row.empty()) << r.out;
  const auto column = header.find("tracker");
  ASSERT_NE(column, std::string::npos) << header;
  // The tracker's name starts where its heading does, after at least two spaces.
  EXPECT_EQ(row.substr(column, 4), "abcd") << header << "\n" << row;
  EXPECT_EQ(row.substr(column - 2, 2), "  ") << header << "\n" << row;
  EXPECT_NE(row.find("(0.01235, 0.01235, 0.01235)"), std::string::npos) << row;
}

TEST(Reporting, OneAgentOneInputAndTheSearchSaysWhatItChanged) {
  const std::string file = write_temp(
      "one_agent.yaml",
      pendulum_with("tracker: abcd\n", std::string("tracker: never\nplugin_paths: [") + NEVER_TRACKER_DIR + "]\n"));
  const std::string out = file + ".out";
  const auto r = run_marsyn("solve " + file + " --runs 5 --global-budget 0 --out " + out);
  EXPECT_EQ(r.code, 1) << r.err;  // `never` finds no controller, by design
  EXPECT_NE(r.err.find("[solve] pendulum-swing-up: 1 agent, planner altro"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("on the product system (2 states, 1 input)"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("1 agents"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("1 inputs"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("search        stopped: no controller for pendulum; no lever left after 2 rounds and "),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("  pendulum     eps (0.2,0.2) -> (0.25,0.25) (round 2: no controller for pendulum)"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("over 2 planning rounds"), std::string::npos) << r.out;
  // result.json and the report carry the same record.
  const std::string result = marsyn::test::slurp(out + "/result.json");
  EXPECT_NE(result.find("\"stop_message\": \"stopped: no controller for pendulum"), std::string::npos);
  EXPECT_NE(result.find("\"from\": \"(0.2,0.2)\""), std::string::npos);
  // The clearances the verdict is about, resolved (the pendulum's file gives none: 0, inf-norm).
  const auto delta = result.find("\"delta\": {");
  ASSERT_NE(delta, std::string::npos) << result;
  const std::string clearances = result.substr(delta, result.find('}', delta) - delta);
  for (const char* part : {"\"agents\": 0.0", "\"obstacles\": 0.0", "\"bounds\": 0.0", "\"norm\": \"inf\""})
    EXPECT_NE(clearances.find(part), std::string::npos) << part << " in " << clearances;
  const std::string page = marsyn::test::slurp(out + "/report.html");
  EXPECT_NE(page.find("\"to\":\"(0.25,0.25)\""), std::string::npos);
}

// What each stage added to the process at its peak, beside `check`'s predictions (plan, tracking, verification), in
// the summary and in result.json (issue 50 item 4).
TEST(Reporting, SolveSaysWhatEachStageAddedToMemory) {
  const std::string file = std::string(MARSYN_SOURCE_DIR) + "/examples/pendulum.yaml";
  const std::string out = write_temp("stage_memory.yaml", "") + ".out";
  const auto r = run_marsyn("solve " + file + " --runs 5 --global-budget 0 --out " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto line = r.out.find("memory        added at each stage's peak: plan ");
  ASSERT_NE(line, std::string::npos) << r.out;
  const std::string text = r.out.substr(line, r.out.find('\n', line) - line);
  for (const char* part : {" MB predicted), tracking ", " MB predicted at most), ", ", verification ", " MB predicted)"})
    EXPECT_NE(text.find(part), std::string::npos) << part << " in " << text;
  const std::string result = marsyn::test::slurp(out + "/result.json");
  const auto memory = result.find("\"memory\": {");
  ASSERT_NE(memory, std::string::npos) << result;
  for (const char* key : {"\"plan\": {", "\"tracking\": {", "\"verification\": {", "\"added_bytes\": ",
                          "\"plan_predicted_bytes\": ", "\"tracking_predicted_bytes\": ", "\"verification_predicted_bytes\": "})
    EXPECT_NE(result.find(key, memory), std::string::npos) << key;
}

TEST(Reporting, PlanWritesOneCsvFileInTheSingular) {
  const std::string file = write_temp("one_csv.yaml", pendulum_with("tracker: abcd\n", "tracker: abcd\n"));
  const auto r = run_marsyn("plan " + file + " --out " + file + ".plan");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find(" and 1 CSV file\n"), std::string::npos) << r.out;
}

}  // namespace
