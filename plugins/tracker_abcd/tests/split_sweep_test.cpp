// One agent's sweep split over ranks (split_sweep.hpp), with threads playing the ranks: every
// rank ends with the controller one process writes, byte for byte, whatever the rank count.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <thread>

#include "abcd_tracker.hpp"
#include "track_scenarios.hpp"
#include "thread_collective.hpp"

using namespace marsyn;
using Steps = std::vector<long long>;  // a figure counted per step (TrackerStats::figures)
using namespace marsyn::abcd;

namespace {

std::string bytes_of(const TrackResult& r, const std::string& name) {
  const std::string path = ::testing::TempDir() + "/" + name;
  r.controller->write(path);
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs `ranks` ranks of one split track; returns each rank's result.
std::vector<TrackResult> track_split(const TrackingProblem& p, int ranks, int threads) {
  AbcdTracker tracker;
  abcd::testing::ThreadGroup group(ranks);
  std::vector<TrackResult> out(static_cast<size_t>(ranks));
  std::vector<std::thread> pool;
  for (int r = 0; r < ranks; ++r)
    pool.emplace_back([&, r] {
      abcd::testing::ThreadCollective c(group, r);
      TrackOptions o;
      o.threads = threads;
      o.collective = &c;
      out[static_cast<size_t>(r)] = tracker.track(p, o);
    });
  for (auto& t : pool) t.join();
  return out;
}

}  // namespace

TEST(SplitSweep, EveryRankHoldsTheSingleProcessController) {
  for (const char* name : {"drone", "crane"}) {
    const auto p = std::string(name) == "drone" ? scenarios::drone(20) : scenarios::crane(3);
    AbcdTracker tracker;
    TrackOptions one;
    one.threads = 1;
    int steps = 0;
    one.progress = [&](int done, int total) {
      EXPECT_EQ(done, steps + 1);
      steps = done;
      EXPECT_EQ(total, static_cast<int>(p.nominal.x.size()) - 1);
    };
    const TrackResult single = tracker.track(p, one);
    ASSERT_EQ(single.status, TrackerStatus::ControllerFound) << name << ": " << single.message;
    EXPECT_EQ(steps, static_cast<int>(p.nominal.x.size()) - 1) << "progress after every backward step";
    const std::string want = bytes_of(single, std::string(name) + "-1.ctrl");
    // The drone on 2 ranks of one thread, the crane (a column per cart position line) on 3 ranks
    // of 2 threads each: one split each keeps the test short.
    const auto [ranks, threads] = std::string(name) == "drone" ? std::pair{2, 1} : std::pair{3, 2};
    {
      const auto results = track_split(p, ranks, threads);
      for (int r = 0; r < ranks; ++r) {
        const TrackResult& got = results[static_cast<size_t>(r)];
        ASSERT_EQ(got.status, TrackerStatus::ControllerFound) << name << " rank " << r << ": " << got.message;
        EXPECT_TRUE(bytes_of(got, std::string(name) + "-split.ctrl") == want)
            << name << ": rank " << r << " of " << ranks << " holds another controller";
        EXPECT_EQ(got.stats.boxes_computed, single.stats.boxes_computed) << name << ": boxes summed over the ranks";
        EXPECT_EQ(got.stats.get<Steps>("winning_cells_per_step"), single.stats.get<Steps>("winning_cells_per_step"));
        EXPECT_EQ(got.controller->period_enclosures().size(), single.controller->period_enclosures().size());
      }
    }
  }
}

TEST(SplitSweep, ANoControllerOutcomeIsTheSameOnEveryRank) {
  auto p = scenarios::drone(40);
  p.input_bounds = {scenarios::vec({-0.3, -0.3}), scenarios::vec({0.3, 0.3})};  // too slow to follow the nominal
  AbcdTracker tracker;
  TrackOptions one;
  one.threads = 1;
  const TrackResult single = tracker.track(p, one);
  ASSERT_NE(single.status, TrackerStatus::ControllerFound);
  for (const TrackResult& got : track_split(p, 2, 1)) {
    EXPECT_EQ(got.status, single.status);
    EXPECT_EQ(got.message, single.message);
    EXPECT_EQ(got.stats.get<Steps>("winning_cells_per_step"), single.stats.get<Steps>("winning_cells_per_step"));
  }
}
