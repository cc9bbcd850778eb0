// Per-agent tracker choice as a user writes it (docs/problem-format.md, "tracker"): a name or a
// block at the top level, in `defaults` or per agent (the agent's own wins), and `auto`, the
// default, which asks every installed tracker's assessment and takes the cheapest ok one. The
// test-only tracker `never` (tests/fixtures/never_tracker.cpp, loaded through plugin_paths)
// accepts every agent at zero estimated cost except those named refuse*.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <regex>

#include "run.hpp"

using marsyn::test::write_temp;

namespace {

// Two unicycles; TOP is replaced by top-level lines, A_EXTRA and B_EXTRA by agent lines.
const std::string kTwo = R"(name: two
tau: 0.1
horizon: 20
delta: 0.2
TOP
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
A_EXTRA
  - name: b
    x0: [0, 6, 0]
    goal: {center: [5, 6, 0], radius: [0.3, 0.3, 0.4]}
    eta_x: [0.025, 0.025, 0.03]
B_EXTRA
)";

std::string problem(const std::string& top, const std::string& a_extra = "", const std::string& b_extra = "") {
  std::string s = kTwo;
  s.replace(s.find("TOP"), 3, top);
  s.replace(s.find("A_EXTRA"), 7, a_extra);
  s.replace(s.find("B_EXTRA"), 7, b_extra);
  return s;
}

const std::string kNever = std::string("plugin_paths: [") + NEVER_TRACKER_DIR + "]";

// A copy of marsyn whose own plugin folder holds only abcd, the unicycle and altro: the tests then do
// not depend on which other trackers the build installs (funnel would take these agents under
// auto). The test tracker comes in through plugin_paths where a test wants it.
std::string marsyn_with_abcd_only() {
  namespace fs = std::filesystem;
  static const std::string exe = [] {
    const fs::path root = marsyn::test::process_temp_dir("marsyn_iso_");
    const fs::path from = fs::path(MARSYN_EXE).parent_path() / "../lib/marsyn/plugins";
    fs::remove_all(root);
    fs::create_directories(root / "bin");
    fs::create_directories(root / "lib/marsyn/plugins");
    fs::copy_file(MARSYN_EXE, root / "bin/marsyn");
    for (const char* lib : {"libmarsyn_tracker_abcd.so", "libmarsyn_dynamics_unicycle.so", "libmarsyn_planner_altro.so"})
      fs::create_symlink(fs::canonical(from / lib), root / "lib/marsyn/plugins" / lib);
    return (root / "bin/marsyn").string();
  }();
  return exe;
}

marsyn::test::RunResult check(const std::string& file) {
  return marsyn::test::run_exe(marsyn_with_abcd_only(), "check " + file);
}

// The summary line of `marsyn check` for one agent.
std::string agent_line(const std::string& out, const std::string& agent) {
  std::smatch m;
  if (std::regex_search(out, m, std::regex("\n" + agent + " +unicycle[^\n]*"))) return m.str().substr(1);
  return "";
}

}  // namespace

TEST(TrackerChoice, AutoIsTheDefaultAndShowsTheAssessment) {
  const auto r = check(write_temp("auto_default.yaml", problem("")));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("tracker auto,"), std::string::npos) << r.out;
  // abcd is the only tracker installed here: chosen, with its own figures (floor(2 eps / eta)).
  EXPECT_NE(agent_line(r.out, "a").find("abcd (auto): <= 4096 tube cells/step, 196 grid inputs"), std::string::npos)
      << r.out;
}

TEST(TrackerChoice, PerAgentOverridesTheTopLevel) {
  const auto r = check(write_temp("per_agent.yaml", problem(kNever + "\ntracker: never", "",
                                                                           "    tracker: {name: abcd, params: {substeps: 3}}")));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(agent_line(r.out, "a").find("never: never a controller"), std::string::npos) << r.out;
  EXPECT_EQ(agent_line(r.out, "a").find("(auto"), std::string::npos) << r.out;
  EXPECT_NE(agent_line(r.out, "b").find("abcd: <= 4096"), std::string::npos) << r.out;
  // `defaults.tracker` applies to agents without their own; a plain name works per agent too.
  const auto d = check(write_temp("per_default.yaml",
                                                  problem(kNever + "\ntracker: abcd", "    tracker: auto", "")));
  ASSERT_EQ(d.code, 0) << d.err;
  EXPECT_NE(agent_line(d.out, "a").find("never (auto, then abcd)"), std::string::npos) << d.out;
  EXPECT_NE(agent_line(d.out, "b").find("abcd: <= 4096"), std::string::npos) << d.out;
}

TEST(TrackerChoice, AutoTakesTheCheapestOkTracker) {
  // never (zero estimated work) before abcd; abcd stays as the fallback.
  auto r = check(write_temp("auto_cheapest.yaml", problem(kNever)));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(agent_line(r.out, "a").find("never (auto, then abcd)"), std::string::npos) << r.out;
  // An agent without eta_x: abcd refuses it, never remains, without a fallback.
  std::string yaml = problem(kNever);
  yaml.replace(yaml.find("    eta_x: [0.025, 0.025, 0.03]\n"), 33, "");
  r = check(write_temp("auto_no_grid.yaml", yaml));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(agent_line(r.out, "a").find("never (auto): never a controller"), std::string::npos) << r.out;
}

TEST(TrackerChoice, NoTrackerOkIsOneLocatedError) {
  // abcd refuses x0's cell in coordinate 0 (eta_x 0.5 > eps 0.2), never refuses the name: the
  // error is located at the field the first tracker names and gives each tracker's reason.
  std::string yaml = problem(kNever);
  yaml.replace(yaml.find("  - name: a"), 11, "  - name: refuse_a");
  yaml.replace(yaml.find("eta_x: [0.025, 0.025, 0.03]"), 27, "eta_x: [0.5, 0.025, 0.03]");
  const std::string file = write_temp("none_ok.yaml", yaml);
  const auto r = check(file);
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_EQ(r.err.rfind("error: " + file + ":18:13: agents[0].eta_x[0]: no installed tracker accepts this agent "
                        "(tracker: auto): abcd: x0's grid cell [0, 0.5] in 'x' does not fit inside the tube",
                        0),
            0u)
      << r.err;
  EXPECT_NE(r.err.find("; never: the test tracker refuses agents named refuse*"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  // Named explicitly, only that tracker's reason, at its own field.
  const std::string named = write_temp("none_ok_named.yaml", problem(kNever + "\ntracker: never", "", ""));
  std::string text = marsyn::test::slurp(named);
  text.replace(text.find("  - name: b"), 11, "  - name: refuse_b");
  const auto n = check(write_temp("none_ok_named.yaml", text));
  EXPECT_EQ(n.code, 2) << n.err;
  EXPECT_NE(n.err.find(":12:14: defaults.eps[1]: the test tracker refuses agents named refuse*\n"), std::string::npos)
      << n.err;
}

TEST(TrackerChoice, OnlyTrackerInstalledKeepsItsMessage) {
  // With abcd alone, auto's refusal is abcd's located message, plus why no other was tried.
  std::string yaml = problem("");
  yaml.replace(yaml.find("eta_x: [0.025, 0.025, 0.03]"), 27, "eta_x: [0.5, 0.025, 0.03]");
  const std::string file = write_temp("only_abcd.yaml", yaml);
  const auto r = check(file);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("error: " + file + ":18:13: agents[0].eta_x[0]: x0's grid cell [0, 0.5] in 'x' does not fit", 0), 0u)
      << r.err;
  EXPECT_NE(r.err.find("choose eta_x <= eps (0.2) (tracker: auto, and abcd is the only tracker installed)"),
            std::string::npos)
      << r.err;
}

TEST(TrackerChoice, MissingGridIsAbcdsLocatedError) {
  std::string yaml = problem("tracker: abcd");
  yaml.replace(yaml.find("    eta_x: [0.025, 0.025, 0.03]\n"), 33, "");
  const std::string file = write_temp("no_grid.yaml", yaml);
  const auto r = check(file);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("error: " + file + ":15:5: agents[0]: the abcd tracker needs 'eta_x', the cell size of its state grid "
                        "(3 positive numbers, each at most eps, e.g. eps / 8 = [0.025, 0.025, 0.03]);",
                        0),
            0u)
      << r.err;
}

TEST(TrackerChoice, BadTrackerFieldsAreLocated) {
  auto r = check(write_temp("typo.yaml", problem("", "", "    tracker: abdc")));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(": agents[1].tracker: unknown tracker plugin 'abdc' (did you mean 'abcd'?)"), std::string::npos)
      << r.err;
  r = check(write_temp("auto_params.yaml", problem("tracker: {name: auto, params: {substeps: 3}}")));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(": tracker.params: 'auto' takes no parameters"), std::string::npos) << r.err;
  r = check(write_temp("agent_params.yaml", problem("", "    tracker: {name: abcd, params: {substeps: 0}}")));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(": agents[0].tracker.params.substeps: "), std::string::npos) << r.err;
}

TEST(TrackerChoice, AFallbackControllerFromTrackIsReadBackByItsTracker) {
  // Under auto, `never` (cheapest) gives no controller and abcd writes a.ctrl; `marsyn verify`
  // on that folder must read the file with abcd (recorded in a.track.json), not with the
  // agent's first choice.
  namespace fs = std::filesystem;
  // 5 m in 4 s: slow enough for abcd on the straight line.
  std::string yaml = problem(kNever);
  yaml.replace(yaml.find("horizon: 20"), 11, "horizon: 40");
  const std::string file = write_temp("auto_fallback.yaml", yaml);
  const fs::path dir = fs::temp_directory_path() / ("marsyn_auto_fallback_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string exe = marsyn_with_abcd_only();
  for (const char* agent : {"a", "b"}) {
    const auto t = marsyn::test::run_exe(exe, std::string("track ") + file + " --agent " + agent +
                                                  " --plan straight-line --out " + dir.string());
    ASSERT_EQ(t.code, 0) << t.out << t.err;
    EXPECT_NE(t.out.find("tracker             abcd (chosen by tracker: auto)"), std::string::npos) << t.out;
    EXPECT_NE(t.err.find("never"), std::string::npos) << t.err;  // tried first, no controller
  }
  const auto v = marsyn::test::run_exe(exe, "verify " + file + " --controllers " + dir.string() +
                                                " --plan straight-line --runs 8");
  EXPECT_NE(v.code, 2) << v.err;
  EXPECT_NE(v.out.find("8 closed-loop runs"), std::string::npos) << v.out << v.err;
  fs::remove_all(dir);
}
