// A stated initial set (docs/problem-format.md, `x0: {center, radius}` or `x0_radius`): the
// controllers accept the whole box at step 0, the closed-loop runs start in it (a vertex under
// the adversary), result.json records it, and controllers made for a smaller set are caught by
// `verify` and tracked again by `solve --resume`.
#include <gtest/gtest.h>

#include <filesystem>

#include "run.hpp"

namespace fs = std::filesystem;
using marsyn::test::run_marsyn;
using marsyn::test::slurp;
using marsyn::test::write_temp;

namespace {

// The pendulum example with `tracker` and the start x0 +- radius.
std::string pendulum(const std::string& tracker, const std::string& radius) {
  std::string s = slurp(std::string(MARSYN_SOURCE_DIR) + "/examples/pendulum.yaml");
  s.replace(s.find("tracker: abcd\n"), 14, "tracker: " + tracker + "\n");
  s.replace(s.find("    x0: [0, 0]\n"), 15, "    x0: {center: [0, 0], radius: " + radius + "}\n");
  return s;
}

class InitialSet : public ::testing::TestWithParam<std::string> {};

TEST_P(InitialSet, IsVerifiedFromEveryStartAndRecorded) {
  const std::string tracker = GetParam();
  const fs::path out = fs::temp_directory_path() / ("marsyn_initial_set_" + tracker + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string cfg = write_temp("initial_set_" + tracker + ".yaml", pendulum(tracker, "[0.05, 0.05]"));
  const auto check = run_marsyn("check " + cfg);
  EXPECT_NE(check.out.find("x0 +-"), std::string::npos) << check.out;
  EXPECT_NE(check.out.find("(0.05, 0.05)"), std::string::npos) << check.out;
  const auto r = run_marsyn("solve " + cfg + " --runs 200 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("status        VERIFIED"), std::string::npos) << r.out;
  EXPECT_NE(slurp((out / "result.json").string()).find("\"x0_radius\": ["), std::string::npos);

  // The same controllers against a wider stated set: runs start at its vertices, which the
  // controllers were not made for.
  const std::string wider = write_temp("initial_set_wider_" + tracker + ".yaml", pendulum(tracker, "[0.15, 0.15]"));
  const auto v = run_marsyn("verify " + wider + " --controllers " + out.string() + " --runs 50");
  EXPECT_EQ(v.code, 1) << v.out << v.err;
  EXPECT_NE(v.out.find("had no input at step 0"), std::string::npos) << v.out;
  // The pendulum has no obstacle, pair or formation: said so, not printed as 1e+300.
  EXPECT_NE(v.out.find("between       obstacle none, collision none, formation none"), std::string::npos) << v.out;
  const auto same = run_marsyn("verify " + cfg + " --controllers " + out.string() + " --runs 50");
  EXPECT_EQ(same.code, 0) << same.out << same.err;

  // --resume with the wider set keeps the plan but not the controller.
  const fs::path again = out.string() + "_wider";
  const auto resumed = run_marsyn("solve " + wider + " --resume " + out.string() + " --runs 50 --out " + again.string());
  EXPECT_NE(resumed.err.find("pendulum's controller was made for another initial set (x0_radius) or disturbance (W): tracked again"), std::string::npos)
      << resumed.err;
  EXPECT_NE(resumed.err.find("[track] "), std::string::npos) << resumed.err;
  fs::remove_all(out);
  fs::remove_all(again);
}

INSTANTIATE_TEST_SUITE_P(Trackers, InitialSet, ::testing::Values("funnel", "abcd"));

// A tracker that does not declare TrackerCapabilities::initial_set (the test tracker `never`) is
// not handed an agent with a stated initial set: refused at load, with where and why.
TEST(InitialSetRefused, ByATrackerWithoutTheCapability) {
  std::string s = pendulum("never", "[0.05, 0.05]");
  s.replace(s.find("tracker: never\n"), 15, std::string("tracker: never\nplugin_paths: [") + NEVER_TRACKER_DIR + "]\n");
  const auto r = run_marsyn("check " + write_temp("initial_set_never.yaml", s));
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("never does not take a stated initial set (x0_radius)"), std::string::npos) << r.err;
  // Without the stated set the same file is accepted.
  s.replace(s.find("{center: [0, 0], radius: [0.05, 0.05]}"), 38, "[0, 0]");
  EXPECT_EQ(run_marsyn("check " + write_temp("initial_set_never_point.yaml", s)).code, 0);
}

}  // namespace

// --resume from a solve whose x0 was elsewhere: the plan is not this problem's (its first state is
// the old x0), so the search plans afresh instead of keeping controllers made around the old start.
TEST(InitialSetResume, APlanFromAnotherStartIsNotKept) {
  const fs::path out = fs::temp_directory_path() / ("marsyn_initial_set_moved_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string cfg = write_temp("initial_set_before.yaml", pendulum("funnel", "[0.05, 0.05]"));
  ASSERT_EQ(run_marsyn("solve " + cfg + " --runs 20 --out " + out.string()).code, 0);
  std::string moved = pendulum("funnel", "[0.05, 0.05]");
  moved.replace(moved.find("center: [0, 0]"), 14, "center: [0.02, 0]");
  const fs::path again = out.string() + "_moved";
  const auto r = run_marsyn("solve " + write_temp("initial_set_moved.yaml", moved) + " --resume " + out.string() +
                            " --runs 20 --out " + again.string());
  EXPECT_NE(r.err.find("pendulum's plan starts elsewhere than x0: planning afresh"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("status        VERIFIED"), std::string::npos) << r.out;
  fs::remove_all(out);
  fs::remove_all(again);
}
