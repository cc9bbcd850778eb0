// Nothing is lost at a stop (docs/search.md, "Stops"): SIGTERM (an outer `timeout`, a job
// limit) or SIGINT during tracking ends `marsyn solve` with result.json (status "stopped",
// partial), plan.json, the controllers found so far and report.html. The test tracker `never`
// (tests/fixtures/never_tracker.cpp) holds an agent named stall* for 3 s, so that the signal
// arrives while the other agent's controller is already found.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "run.hpp"

namespace fs = std::filesystem;
using marsyn::test::slurp;
using marsyn::test::write_temp;

namespace {

std::string two_agents() {
  std::string s = slurp(std::string(MARSYN_SOURCE_DIR) + "/examples/pendulum.yaml");
  s.replace(s.find("tracker: abcd\n"), 14, std::string("tracker: funnel\nplugin_paths: [") + NEVER_TRACKER_DIR + "]\npairwise_collision: false\n");
  const std::string agent = s.substr(s.find("  - name: pendulum\n"));
  std::string stall = agent;
  stall.replace(stall.find("name: pendulum"), 14, "name: stall_pendulum\n    tracker: never");
  return s + stall;
}

// How a signalled run ended: whether the signal went out, whether marsyn ended within the limit,
// and its wait status.
struct Signalled {
  bool signalled = false, ended = false;
  int status = 0;
};

// Starts `marsyn ARGS` in the background (stdout to LOG.out, stderr to LOG), sends `sig` once
// LOG shows `trigger` (after `delay`), and waits at most `limit` for it to end (then kills it).
Signalled run_and_signal(const std::string& args, const fs::path& log, const std::string& trigger, int sig,
                         std::chrono::seconds limit, std::chrono::milliseconds delay = std::chrono::milliseconds(0)) {
  // A log left by an earlier run with the same pid would be read before the child's shell
  // truncates it, and the signal would arrive before marsyn can catch it (a CI run failed so).
  fs::remove(log);
  fs::remove(log.string() + ".out");
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string cmd = std::string("exec ") + MARSYN_EXE + " " + args + " >" + log.string() + ".out 2>" + log.string();
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  Signalled r;
  const auto start = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - start < limit) {
    if (::waitpid(pid, &r.status, WNOHANG) == pid) {
      r.ended = true;
      return r;
    }
    if (!r.signalled && slurp(log.string()).find(trigger) != std::string::npos) {
      std::this_thread::sleep_for(delay);
      ::kill(pid, sig);
      r.signalled = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, &r.status, 0);
  return r;
}

// A solve signalled once its log shows the first agent's controller; its exit status (-1 when it
// did not end within 60 s).
int solve_and_signal(const std::string& args, const fs::path& log, int sig, bool& signalled) {
  const Signalled r = run_and_signal(args, log, "] pendulum (funnel): controller,", sig, std::chrono::seconds(60));
  signalled = r.signalled;
  return r.ended ? r.status : -1;
}

void expect_partial_result(int sig, const std::string& name, bool resume = false) {
  const fs::path out = fs::temp_directory_path() / ("marsyn_stop_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(out);
  const std::string cfg = write_temp(name + ".yaml", two_agents());
  bool signalled = false;
  const int status = solve_and_signal("solve " + cfg + " --out " + out.string() + " --runs 5", out.string() + ".log", sig, signalled);
  ASSERT_TRUE(signalled) << slurp(out.string() + ".log");
  ASSERT_NE(status, -1) << "marsyn did not end after the signal";
  ASSERT_TRUE(WIFEXITED(status)) << "ended by the signal itself, with nothing written";
  EXPECT_EQ(WEXITSTATUS(status), 1);
  const std::string result = slurp((out / "result.json").string());
  EXPECT_NE(result.find("\"status\": \"stopped\""), std::string::npos) << result.substr(0, 400);
  EXPECT_NE(result.find("\"partial\": true"), std::string::npos);
  EXPECT_NE(result.find("a stop was requested (SIGINT or SIGTERM)"), std::string::npos);
  // What a longer run would have done next, with its predicted time.
  EXPECT_NE(result.find("the best lever untried: enlarge eps by 1.25 and re-plan (about "), std::string::npos) << result.substr(0, 600);
  EXPECT_TRUE(fs::exists(out / "pendulum.ctrl"));
  EXPECT_FALSE(fs::exists(out / "stall_pendulum.ctrl"));
  EXPECT_TRUE(fs::exists(out / "plan.json"));
  EXPECT_NE(slurp((out / "report.html").string()).find("STOPPED"), std::string::npos);
  EXPECT_NE(slurp(out.string() + ".log.out").find("status        STOPPED"), std::string::npos);
  // An agent the stop kept from being tracked is not "invalid input".
  EXPECT_EQ(slurp(out.string() + ".log.out").find("invalid input"), std::string::npos);
  if (resume) {
    // --resume keeps the plan and pendulum's controller and tracks only the other agent (here with
    // the funnel, which finds one): verified without planning or tracking pendulum again.
    std::string again = two_agents();
    again.replace(again.find("tracker: never"), 14, "tracker: funnel");
    const fs::path out2 = out.string() + "_resumed";
    const auto r = marsyn::test::run_marsyn("solve " + write_temp(name + "_again.yaml", again) + " --resume " + out.string() +
                                            " --out " + out2.string() + " --runs 5");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("[search] resumed from " + out.string() + ": its plan (T = "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(") and 1 controller; the plan is eps-robust with the recorded tubes"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("[track] 1 agent(s) keep their controllers (nominal and parameters unchanged); tracking 1"), std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("[plan] altro on the product system"), std::string::npos) << "no planning on resume";
    EXPECT_NE(r.out.find("status        VERIFIED"), std::string::npos) << r.out;
    fs::remove_all(out2);
  }
  fs::remove_all(out);
}

TEST(Stop, SigtermDuringTrackingLeavesAReadablePartialResult) { expect_partial_result(SIGTERM, "term"); }

TEST(Stop, SigintDuringTrackingLeavesAReadablePartialResult) { expect_partial_result(SIGINT, "int"); }

TEST(Stop, ResumeKeepsThePlanAndTheControllersFound) { expect_partial_result(SIGTERM, "resume", true); }

// The time limit ends a synthesis in progress, not only the rounds between them: the run's stop
// request reaches the tracker (TrackOptions::stop). The test tracker holds hold_pendulum until it
// is asked to stop (60 s otherwise).
TEST(Stop, TheTimeLimitEndsASynthesisInProgress) {
  std::string s = two_agents();
  s.replace(s.find("name: stall_pendulum"), 20, "name: hold_pendulum");
  const fs::path out = fs::temp_directory_path() / ("marsyn_stop_hold_" + std::to_string(::getpid()));
  fs::remove_all(out);
  // 3 s: the pendulum's funnel (1.1 s under the sanitizers on a loaded machine) ends first, so
  // hold_pendulum's synthesis is the one in progress when the limit comes.
  const auto r = marsyn::test::run_marsyn("solve " + write_temp("hold.yaml", s) + " --time-limit 3 --out " + out.string() +
                                          " --runs 5");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("hold_pendulum (never): resource limit"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("the test tracker was stopped by the run"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("the time limit (3 s) was reached in round 1 (no controller for hold_pendulum; the stop cut short "
                       "the synthesis of hold_pendulum)"),
            std::string::npos)
      << r.out;
  // A synthesis cut short is no dead end: the stop message names what would have come next.
  EXPECT_NE(r.out.find("the best lever untried: enlarge eps by 1.25 and re-plan (about "), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(out / "result.json"));
  EXPECT_TRUE(fs::exists(out / "pendulum.ctrl"));
  fs::remove_all(out);
}

TEST(Stop, ResumeFromAFolderWithoutAPlanIsRefused) {
  const fs::path empty = fs::temp_directory_path() / ("marsyn_resume_empty_" + std::to_string(::getpid()));
  fs::create_directories(empty);
  const auto r = marsyn::test::run_marsyn("solve " + write_temp("resume_empty.yaml", two_agents()) + " --resume " + empty.string() +
                                          " --out " + (empty / "out").string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--resume"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("result.json is missing"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(empty / "out" / "result.json"));
  fs::remove_all(empty);
}

}  // namespace

// `marsyn plan` stops too (the helper of issue 49 found it killed with nothing written): the
// signal ends the horizon search after the solve in progress, and plan.json and the summary hold
// the best attempt so far.
TEST(Stop, APlanStopsAfterTheSolveInProgressAndWritesItsBest) {
  const fs::path out = fs::temp_directory_path() / ("marsyn_stop_plan_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const fs::path log = out.string() + ".log";
  const Signalled r = run_and_signal(std::string("plan ") + MARSYN_SOURCE_DIR + "/tests/continuous/vehicle_maze.yaml --out " + out.string(),
                                     log, "[plan] T = 400:", SIGINT, std::chrono::seconds(120));
  const bool signalled = r.signalled, ended = r.ended;
  const int status = r.status;
  ASSERT_TRUE(signalled) << slurp(log.string());
  ASSERT_TRUE(ended) << "marsyn plan did not end after the signal";
  ASSERT_TRUE(WIFEXITED(status)) << "ended by the signal itself, with nothing written";
  EXPECT_EQ(WEXITSTATUS(status), 1);
  const std::string said = slurp(log.string()), printed = slurp(log.string() + ".out");
  EXPECT_NE(said.find("stopped: no further horizons tried"), std::string::npos) << said;
  EXPECT_EQ(said.find("T = 782"), std::string::npos) << said;
  EXPECT_NE(printed.find("NO FEASIBLE PLAN"), std::string::npos) << printed;
  EXPECT_TRUE(fs::exists(out / "plan.json"));
  fs::remove_all(out);
}

// `marsyn track` stops too: SIGINT during a synthesis ends it through the tracker's stop request
// (status "resource limit" with the tracker's words), not by the signal with nothing said.
TEST(Stop, ATrackStopsTheSynthesisInProgress) {
  std::string s = two_agents();
  s.replace(s.find("name: stall_pendulum"), 20, "name: hold_pendulum");
  const std::string cfg = write_temp("track_hold.yaml", s);
  const fs::path out = fs::temp_directory_path() / ("marsyn_stop_track_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const fs::path log = out.string() + ".log";
  const auto start = std::chrono::steady_clock::now();
  // The signal a little after the hold began: inside the tracker, not in planning.
  const Signalled r = run_and_signal("track " + cfg + " --agent hold_pendulum --out " + out.string(), log,
                                     "hold_pendulum with never", SIGINT, std::chrono::seconds(50), std::chrono::milliseconds(200));
  const bool signalled = r.signalled, ended = r.ended;
  const int status = r.status;
  const std::string said = slurp(log.string()), printed = slurp(log.string() + ".out");
  ASSERT_TRUE(signalled) << said;
  ASSERT_TRUE(ended) << "marsyn track did not end after the signal (the hold lasts 60 s)";
  ASSERT_TRUE(WIFEXITED(status)) << "ended by the signal itself, with nothing said";
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(40));
  EXPECT_NE(printed.find("resource limit: the test tracker was stopped by the run"), std::string::npos) << printed << said;
  EXPECT_TRUE(fs::exists(out / "hold_pendulum.track.json"));
  fs::remove_all(out);
}
