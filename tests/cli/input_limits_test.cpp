// Bad input that cannot live in a file of tests/bad_inputs (directories, devices, a file over the
// size limit, the memory budget from the environment), the exact start geometry on inputs that
// must be accepted, and the output folder: nothing is written outside it.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "run.hpp"

namespace fs = std::filesystem;
using marsyn::test::run_marsyn;
using marsyn::test::slurp;
using marsyn::test::write_temp;

namespace {

const std::string kSource = MARSYN_SOURCE_DIR;

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "fixture does not contain: " << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

// A one-line error for `file` with no location.
void expect_file_error(const std::string& file, const std::string& expected) {
  const auto r = run_marsyn("check " + file);
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_EQ(r.err.rfind("error: " + file + ": ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(InputLimits, DirectoryIsNotAProblemFile) {
  const fs::path dir = fs::temp_directory_path() / ("marsyn_dir_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  expect_file_error(dir.string(), "is a directory");
  fs::remove_all(dir);
}

TEST(InputLimits, DevicesAreRefusedBeforeReading) {
  expect_file_error("/dev/zero", "is not a regular file");
  expect_file_error("/dev/null", "is not a regular file");
}

TEST(InputLimits, FifoIsRefusedWithoutBlocking) {
  const fs::path fifo = fs::temp_directory_path() / ("marsyn_fifo_" + std::to_string(::getpid()));
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expect_file_error(fifo.string(), "is not a regular file");
  fs::remove(fifo);
}

TEST(InputLimits, FileOverTheSizeLimit) {
  const std::string file = write_temp("huge.yaml", "tau: 0.1\n");
  fs::resize_file(file, (16u << 20) + 1);  // sparse: no 16 MiB written
  expect_file_error(file, "at most 16777216 bytes (16 MiB)");
}

const std::string kTwo = slurp(kSource + "/tests/bad_inputs/agents_start_too_close.yaml");

TEST(InputLimits, StartGeometryAcceptsWhatTheSpecAllows) {
  // delta_norm 2: (3.9, 3.9) is 0.141 from the corner (4, 4) of the block, more than delta = 0.12;
  // in the inf-norm it is 0.1 away, less than delta: rejected there.
  std::string yaml = slurp(kSource + "/tests/bad_inputs/x0_within_delta_of_obstacle.yaml");
  yaml = replace(yaml, "x0: [3.9, 5, 0]", "x0: [3.9, 3.9, 0]");
  yaml = replace(yaml, "delta: 0.2\n", "delta: 0.12\ndelta_norm: 2\n");
  auto r = run_marsyn("check " + write_temp("corner_two.yaml", yaml));
  EXPECT_EQ(r.code, 0) << r.err;
  r = run_marsyn("check " + write_temp("corner_inf.yaml", replace(yaml, "delta_norm: 2\n", "delta_norm: inf\n")));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("inf-norm distance 0.1 from obstacle 'block', less than delta = 0.12"), std::string::npos) << r.err;
  // Exactly delta away is allowed (the spec is distance >= delta).
  EXPECT_EQ(run_marsyn("check " + write_temp("at_delta2.yaml", replace(kTwo, "x0: [0.15, 2.1, 0]", "x0: [0.2, 2, 0]"))).code, 0);
  // Without pairwise collisions agents may start anywhere.
  r = run_marsyn("check " + write_temp("no_pairs.yaml", replace(kTwo, "delta: 0.2\n", "delta: 0.2\npairwise_collision: false\n")));
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST(InputLimits, MemoryBudgetFromTheCommandLine) {
  const std::string file = kSource + "/examples/multi_drone.yaml";
  EXPECT_EQ(run_marsyn("check --memory-budget 2G " + file).code, 0);
  auto r = run_marsyn("check --memory-budget 100K " + file);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("more than the memory budget of"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(--memory-budget)"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  // The budget travels in the request structs: the environment has no say.
  EXPECT_EQ(run_marsyn("check " + file, "MARSYN_MEMORY_BUDGET=100K").code, 0);
  r = run_marsyn("check --memory-budget lots " + file);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--memory-budget: expected a positive number of bytes"), std::string::npos) << r.err;
}

TEST(InputLimits, EveryExampleStillPasses) {
  for (const auto& e : fs::directory_iterator(kSource + "/examples"))
    if (e.path().extension() == ".yaml") {
      const auto r = run_marsyn("check " + e.path().string());
      EXPECT_EQ(r.code, 0) << e.path() << ": " << r.err;
    }
}

std::set<std::string> files_under(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) out.insert(fs::relative(e.path(), dir).string());
  return out;
}

// A link planted in the output folder is not followed out of it: the write is refused and the
// link's target is never created.
TEST(OutputFolder, PlantedLinkIsNotFollowed) {
  const fs::path scratch = fs::temp_directory_path() / ("marsyn_link_" + std::to_string(::getpid()));
  fs::remove_all(scratch);
  fs::create_directories(scratch / "out");
  fs::create_symlink(scratch / "outside.json", scratch / "out/plan.json");
  const auto r = run_marsyn("plan " + kSource + "/examples/pendulum.yaml --out " + (scratch / "out").string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("refusing to write 'plan.json'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(scratch / "outside.json"));
  EXPECT_EQ(files_under(scratch), (std::set<std::string>{"out", "out/plan.json"}));
  fs::remove_all(scratch);
}

// With a valid problem, plan writes exactly its files, all inside --out; with no --out, inside
// marsyn-out/<problem name>/ of the working directory.
TEST(OutputFolder, PlanWritesOnlyInsideTheFolder) {
  const fs::path scratch = fs::temp_directory_path() / ("marsyn_conf_" + std::to_string(::getpid()));
  fs::remove_all(scratch);
  fs::create_directories(scratch / "cwd");
  const std::string cd = "cd " + (scratch / "cwd").string() + " &&";
  auto r = run_marsyn("plan " + kSource + "/examples/pendulum.yaml --out ../cwd/out", cd);
  EXPECT_EQ(r.code, 0) << r.err;
  r = run_marsyn("plan " + kSource + "/examples/pendulum.yaml", cd);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(files_under(scratch), (std::set<std::string>{"cwd", "cwd/out", "cwd/out/plan.json", "cwd/out/pendulum.csv",
                                                         "cwd/marsyn-out", "cwd/marsyn-out/pendulum-swing-up",
                                                         "cwd/marsyn-out/pendulum-swing-up/plan.json",
                                                         "cwd/marsyn-out/pendulum-swing-up/pendulum.csv"}));
  fs::remove_all(scratch);
}

// An --out that cannot be a folder (a file is in the way) is refused before any work: no
// planning, no synthesis, nothing written, for each command that writes a folder.
TEST(OutputFolder, FileInTheWayFailsBeforeTheWork) {
  const fs::path scratch = fs::temp_directory_path() / ("marsyn_inway_" + std::to_string(::getpid()));
  fs::remove_all(scratch);
  fs::create_directories(scratch);
  std::ofstream(scratch / "taken") << "a file, not a folder\n";
  const std::string problem = kSource + "/examples/pendulum.yaml";
  for (const std::string cmd : {"solve " + problem, "plan " + problem, "track " + problem + " --agent pendulum"}) {
    const auto r = run_marsyn(cmd + " --out " + (scratch / "taken").string());
    EXPECT_EQ(r.code, 2) << cmd << ": " << r.err;
    EXPECT_NE(r.err.find("cannot create the output folder"), std::string::npos) << cmd << ": " << r.err;
    EXPECT_EQ(r.err.find("[plan]"), std::string::npos) << cmd << ": planned before refusing --out:\n" << r.err;
    EXPECT_EQ(r.err.find("[track"), std::string::npos) << cmd << ": tracked before refusing --out:\n" << r.err;
  }
  EXPECT_EQ(files_under(scratch), (std::set<std::string>{"taken"}));
  fs::remove_all(scratch);
}

}  // namespace
