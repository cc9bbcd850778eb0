#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include "agents.hpp"

using namespace marsyn;
using namespace marsyn::abcd;
using marsyn::abcd::testing::agent;

namespace {
std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
void spit(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}
void expect_error(const std::string& path, const std::string& needle) {
  AbcdTracker tracker;
  try {
    tracker.read_controller(path);
    FAIL() << "no error for " << needle;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}
}  // namespace

TEST(ControllerFile, RoundTripAnswersIdentically) {
  const auto& a = agent("drone");
  ASSERT_TRUE(a.result.controller);
  const std::string path = ::testing::TempDir() + "/drone.ctl";
  a.result.controller->write(path);
  AbcdTracker tracker;
  const auto back = tracker.read_controller(path);
  const auto& c = *a.result.controller;
  EXPECT_EQ(back->state_dim(), 3);
  EXPECT_EQ(back->input_dim(), 2);
  EXPECT_EQ(back->horizon(), c.horizon());
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> d(-0.3, 0.3);
  int ok = 0;
  for (int t = 0; t < 20000; ++t) {
    const int k = static_cast<int>(rng() % static_cast<std::uint64_t>(c.horizon() + 2));
    const auto& xk = a.problem.nominal.x[static_cast<size_t>(std::min(k, c.horizon()))];
    double x[3] = {xk[0] + d(rng), xk[1] + d(rng), xk[2] + d(rng)}, u1[2], u2[2];
    const auto s1 = c.input(x, k, u1), s2 = back->input(x, k, u2);
    ASSERT_EQ(s1, s2);
    if (s1 == ControlStatus::Ok) {
      ++ok;
      EXPECT_EQ(u1[0], u2[0]);
      EXPECT_EQ(u1[1], u2[1]);
      EXPECT_GE(u1[0], -2.4);
      EXPECT_LE(u1[0], 2.4);
    }
  }
  EXPECT_GT(ok, 1000);
  // The same bytes once more (write is deterministic).
  const std::string again = ::testing::TempDir() + "/drone2.ctl";
  back->write(again);
  EXPECT_TRUE(slurp(path) == slurp(again));
}

TEST(ControllerFile, StatusesOutsideDomainAndHorizon) {
  const auto& a = agent("drone");
  const auto& c = *a.result.controller;
  double u[2];
  const auto& x0 = a.problem.nominal.x[0];
  EXPECT_EQ(c.input(x0.data(), 0, u), ControlStatus::Ok);
  double far[3] = {x0[0] + 1.0, x0[1], x0[2]};
  EXPECT_EQ(c.input(far, 0, u), ControlStatus::OutsideDomain);
  double nan[3] = {NAN, x0[1], x0[2]};
  EXPECT_EQ(c.input(nan, 0, u), ControlStatus::OutsideDomain);
  EXPECT_EQ(c.input(x0.data(), c.horizon(), u), ControlStatus::OutsideHorizon);
  EXPECT_EQ(c.input(x0.data(), -1, u), ControlStatus::OutsideHorizon);
}

TEST(ControllerFile, CorruptTruncatedAndMismatchedFilesAreClearErrors) {
  const auto& a = agent("vehicle");
  ASSERT_TRUE(a.result.controller);
  const std::string dir = ::testing::TempDir();
  const std::string good = dir + "/vehicle.ctl";
  a.result.controller->write(good);
  const std::string bytes = slurp(good);

  spit(dir + "/trunc.ctl", bytes.substr(0, bytes.size() / 2));
  expect_error(dir + "/trunc.ctl", "truncated");
  spit(dir + "/short.ctl", bytes.substr(0, 12));
  expect_error(dir + "/short.ctl", "truncated");

  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  spit(dir + "/flip.ctl", flipped);
  expect_error(dir + "/flip.ctl", "checksum");

  std::string magic = bytes;
  magic[0] = 'X';
  spit(dir + "/magic.ctl", magic);
  expect_error(dir + "/magic.ctl", "magic");

  std::string version = bytes;
  version[8] = 99;
  spit(dir + "/version.ctl", version);
  expect_error(dir + "/version.ctl", "version");

  spit(dir + "/extra.ctl", bytes + "x");
  expect_error(dir + "/extra.ctl", "size");

  expect_error(dir + "/does-not-exist.ctl", "cannot open");
}
