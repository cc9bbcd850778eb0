#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include "agents.hpp"
#include "successor_cache.hpp"
#include "tube.hpp"

using namespace marsyn;
using Steps = std::vector<long long>;  // a figure counted per step (TrackerStats::figures)
using namespace marsyn::abcd;
using marsyn::abcd::testing::agent;

namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Re-checks stored inputs independently of the synthesis' reuse machinery: the absolute
// successor box of the cell (no shift, no cache) must be covered by winning cells of step k+1.
void expect_stored_inputs_valid(const TrackingProblem& p, const GridController& c, int samples) {
  const auto& d = c.data();
  SuccessorOptions so;
  so.tau = p.tau;
  SuccessorBox sb(*p.dynamics, d.w, so);
  SuccessorTable tab(sb, c.grid(), c.input_grid(), std::vector<bool>(static_cast<size_t>(d.n), false));
  std::mt19937_64 rng(3);
  int checked = 0;
  for (int attempt = 0; attempt < samples * 20 && checked < samples; ++attempt) {
    const int k = static_cast<int>(rng() % static_cast<std::uint64_t>(d.tables()));
    const IndexBox& b = d.boxes[k];
    const std::int64_t l = static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(b.size()));
    const std::uint16_t j = d.inputs[static_cast<size_t>(d.offsets[k] + l)];
    if (j == kLosing) continue;
    std::int64_t idx[kMaxDim];
    b.unlinear(l, idx);
    double lo[kMaxDim], hi[kMaxDim];
    ASSERT_TRUE(tab.absolute(idx, j, lo, hi));
    // Every corner of the box, quantized, must be a winning cell of step k+1 (the quantizer is
    // monotone, so checking the covering index box cell by cell is exact).
    IndexBox cov;
    cov.n = d.n;
    for (int i = 0; i < d.n; ++i) {
      cov.lo[i] = c.grid().index(i, lo[i]);
      cov.hi[i] = c.grid().index(i, hi[i]);
    }
    const IndexBox& nb = d.boxes[k + 1];
    ASSERT_TRUE(nb.contains(cov)) << "step " << k;
    std::int64_t q[kMaxDim];
    for (std::int64_t cl = 0; cl < cov.size(); ++cl) {
      cov.unlinear(cl, q);
      if (k + 1 < d.tables()) {
        ASSERT_NE(d.inputs[static_cast<size_t>(d.offsets[k + 1] + nb.linear(q))], kLosing);
      }
    }
    ++checked;
  }
  EXPECT_EQ(checked, samples);
}

}  // namespace

class ExampleAgents : public ::testing::TestWithParam<std::string> {};

TEST_P(ExampleAgents, GetsAVerifiedController) {
  const auto& a = agent(GetParam());
  ASSERT_EQ(a.result.status, TrackerStatus::ControllerFound) << a.result.message;
  ASSERT_TRUE(a.result.controller);
  EXPECT_TRUE(a.result.stats.get<bool>("initial_state_winning"));
  const auto& s = a.result.stats;
  EXPECT_GT(s.get<long long>("tube_cells"), 0);
  EXPECT_GT(s.boxes_computed, 0);
  EXPECT_EQ(static_cast<int>(s.get<Steps>("winning_cells_per_step").size()), static_cast<int>(a.problem.nominal.x.size()));
  auto* c = dynamic_cast<const GridController*>(a.result.controller.get());
  ASSERT_TRUE(c);
  expect_stored_inputs_valid(a.problem, *c, 300);
}

INSTANTIATE_TEST_SUITE_P(Tracker, ExampleAgents,
                         ::testing::Values("drone", "lane", "formation", "vehicle", "pendulum", "crane"));

TEST(Synthesis, TubeTooThinForTheDisturbanceHasNoController) {
  auto p = scenarios::drone(30);
  p.tube.w = scenarios::vec({0.0, 0.6, 0.6});  // pushes further per step than the tube is wide
  AbcdTracker tracker;
  TrackOptions o;
  o.threads = 1;
  const auto r = tracker.track(p, o);
  EXPECT_EQ(r.status, TrackerStatus::NoController) << r.message;
  EXPECT_FALSE(r.controller);
  EXPECT_FALSE(r.stats.get<bool>("initial_state_winning"));

  auto q = scenarios::vehicle();
  q.tube.eps = scenarios::vec({0.02, 0.03});  // two cells wide, W = 0.1 on the speed
  const auto r2 = tracker.track(q, o);
  EXPECT_EQ(r2.status, TrackerStatus::NoController) << r2.message;
  EXPECT_FALSE(r2.controller);
}

TEST(Synthesis, EpsBelowOneCellIsNoController) {
  auto p = scenarios::vehicle();
  p.tube.eps = scenarios::vec({0.004, 0.12});
  AbcdTracker tracker;
  const auto r = tracker.track(p, TrackOptions{});
  EXPECT_EQ(r.status, TrackerStatus::NoController);
}

TEST(Synthesis, InvalidInputIsReported) {
  auto p = scenarios::vehicle();
  p.tube.eps = scenarios::vec({0.08});
  AbcdTracker tracker;
  EXPECT_EQ(tracker.track(p, TrackOptions{}).status, TrackerStatus::InvalidInput);
  p = scenarios::vehicle();
  p.nominal.x.resize(1);
  EXPECT_EQ(tracker.track(p, TrackOptions{}).status, TrackerStatus::InvalidInput);
}

TEST(Synthesis, OneAndTwoThreadsWriteIdenticalFiles) {
  for (const char* name : {"drone", "crane"}) {
    auto p = std::string(name) == "drone" ? scenarios::drone(40) : scenarios::crane(3);
    AbcdTracker tracker;
    TrackOptions o1, o2;
    o1.threads = 1;
    o2.threads = 2;
    const auto r1 = tracker.track(p, o1);
    const auto r2 = tracker.track(p, o2);
    ASSERT_EQ(r1.status, TrackerStatus::ControllerFound) << name << ": " << r1.message;
    ASSERT_EQ(r2.status, TrackerStatus::ControllerFound) << name << ": " << r2.message;
    const std::string f1 = ::testing::TempDir() + "/det1.ctl", f2 = ::testing::TempDir() + "/det2.ctl";
    r1.controller->write(f1);
    r2.controller->write(f2);
    const std::string b1 = slurp(f1), b2 = slurp(f2);
    EXPECT_GT(b1.size(), 100u);
    EXPECT_TRUE(b1 == b2) << name << ": 1-thread and 2-thread controller files differ";
    EXPECT_EQ(r1.stats.get<Steps>("winning_cells_per_step"), r2.stats.get<Steps>("winning_cells_per_step"));
  }
}

TEST(Synthesis, WinningSetPrefixSumsMatchBruteForce) {
  IndexBox b;
  b.n = 3;
  for (int i = 0; i < 3; ++i) {
    b.lo[i] = -2 + i;
    b.hi[i] = 3 + 2 * i;
  }
  std::mt19937_64 rng(5);
  std::vector<std::uint8_t> win(static_cast<size_t>(b.size()));
  for (auto& w : win) w = (rng() % 10) != 0;
  WinningSet ws(b, win);
  for (int t = 0; t < 2000; ++t) {
    IndexBox q;
    q.n = 3;
    for (int i = 0; i < 3; ++i) {
      std::int64_t a = b.lo[i] + static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(b.extent(i)));
      std::int64_t c = b.lo[i] + static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(b.extent(i)));
      q.lo[i] = std::min(a, c);
      q.hi[i] = std::max(a, c);
    }
    bool all = true;
    std::int64_t idx[kMaxDim];
    for (std::int64_t l = 0; l < q.size(); ++l) {
      q.unlinear(l, idx);
      all = all && win[static_cast<size_t>(b.linear(idx))];
    }
    ASSERT_EQ(ws.all_winning(q), all);
  }
}

TEST(Synthesis, TubeCellsLieEntirelyInTheEpsBox) {
  const auto& a = agent("drone");
  auto* c = dynamic_cast<const GridController*>(a.result.controller.get());
  ASSERT_TRUE(c);
  for (size_t k = 0; k < c->data().boxes.size(); ++k) {
    const IndexBox& b = c->data().boxes[k];
    for (int i = 0; i < b.n; ++i) {
      EXPECT_GE(c->grid().cell(i, b.lo[i]).lower(), a.problem.nominal.x[k][i] - a.problem.tube.eps[i]);
      EXPECT_LE(c->grid().cell(i, b.hi[i]).upper(), a.problem.nominal.x[k][i] + a.problem.tube.eps[i]);
      // and it is the largest such range
      EXPECT_LT(c->grid().cell(i, b.lo[i] - 1).lower(), a.problem.nominal.x[k][i] - a.problem.tube.eps[i]);
      EXPECT_GT(c->grid().cell(i, b.hi[i] + 1).upper(), a.problem.nominal.x[k][i] + a.problem.tube.eps[i]);
    }
  }
}

TEST(ReachAvoid, DoubleIntegratorReachesTargetInClosedLoop) {
  ReachAvoidProblem p;
  p.dynamics = std::make_shared<models::DoubleIntegrator>();
  p.domain = {scenarios::vec({-1, -1}), scenarios::vec({1, 1})};
  p.safe = p.domain;
  p.target = {scenarios::vec({-0.2, -0.2}), scenarios::vec({0.2, 0.2})};
  p.eta_x = scenarios::vec({0.05, 0.05});
  p.eta_u = scenarios::vec({0.25});
  p.w = scenarios::vec({0, 0.02});
  p.input_bounds = {scenarios::vec({-2}), scenarios::vec({2})};
  AbcdTracker tracker;
  TrackOptions o;
  o.threads = 2;
  const auto r = tracker.reach_avoid(p, o);
  ASSERT_EQ(r.status, TrackerStatus::ControllerFound) << r.message;
  const auto& c = *r.controller;
  EXPECT_EQ(c.horizon(), -1);
  std::mt19937_64 rng(9);
  int reached = 0, started = 0;
  for (int t = 0; t < 200; ++t) {
    Eigen::VectorXd x(2);
    x << -0.9 + 1.8 * (rng() % 1000) / 1000.0, -0.9 + 1.8 * (rng() % 1000) / 1000.0;
    double u[1];
    if (c.input(x.data(), 0, u) != ControlStatus::Ok) continue;
    ++started;
    for (int k = 0; k < 400; ++k) {
      const auto s = c.input(x.data(), k, u);
      if (s == ControlStatus::OutsideHorizon) {  // target reached
        ++reached;
        EXPECT_TRUE(p.target.contains(x));
        break;
      }
      ASSERT_EQ(s, ControlStatus::Ok) << "left the winning domain at step " << k;
      const double wv = 0.02 * ((rng() & 1) ? 1 : -1);
      x = integrate_period(*p.dynamics, x, u, 0.1, 50, [&](int) { return scenarios::vec({0, wv}); });
      ASSERT_TRUE(p.safe.contains(x));
    }
  }
  EXPECT_GT(started, 20);
  EXPECT_EQ(reached, started);
}

// Paper Sec. 3.5: the dynamics-aware swing-up (a spiral) is trackable, the geometric straight
// line from (0, 0) to (pi, 0) is not.
TEST(Synthesis, PendulumStraightLineIsNotTrackable) {
  EXPECT_EQ(agent("pendulum").result.status, TrackerStatus::ControllerFound);
  auto p = scenarios::pendulum();
  const int T = 60;
  p.nominal.x.clear();
  p.nominal.u.clear();
  for (int k = 0; k <= T; ++k) p.nominal.x.push_back(scenarios::vec({M_PI * k / T, 0.0}));
  for (int k = 0; k < T; ++k) p.nominal.u.push_back(scenarios::vec({0.0}));
  AbcdTracker tracker;
  TrackOptions o;
  o.threads = 2;
  const auto r = tracker.track(p, o);
  EXPECT_EQ(r.status, TrackerStatus::NoController) << r.message;
  EXPECT_FALSE(r.controller);
}

// A stated initial set (TrackingProblem::initial_radius): the controller is found only when every
// cell of x0 +- radius is winning at step 0, so every state of the box gets an input; a set that
// reaches the tube's losing rim is refused with the count of its losing cells.
TEST(Synthesis, EveryCellOfAStatedInitialSetIsWinning) {
  auto p = scenarios::drone(30);
  p.initial_radius = scenarios::vec({0.05, 0.05, 0.052});
  AbcdTracker tracker;
  TrackOptions o;
  o.threads = 1;
  const auto r = tracker.track(p, o);
  ASSERT_EQ(r.status, TrackerStatus::ControllerFound) << r.message;
  EXPECT_TRUE(r.stats.get<bool>("initial_state_winning"));
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  Eigen::VectorXd x(3), u(2);
  for (int s = 0; s < 4000; ++s) {
    for (int i = 0; i < 3; ++i) x[i] = p.nominal.x[0][i] + (s < 8 ? (s >> i & 1 ? 1 : -1) : U(rng)) * p.initial_radius[i];
    ASSERT_EQ(r.controller->input(x.data(), 0, u.data()), ControlStatus::Ok) << "sample " << s;
  }

  p.initial_radius = p.tube.eps * 0.999;  // the whole tube, whose rim cannot be held against W
  const auto rim = tracker.track(p, o);
  EXPECT_EQ(rim.status, TrackerStatus::NoController);
  EXPECT_NE(rim.message.find("cell(s) of the stated initial set (x0 +- x0_radius) are not winning"), std::string::npos) << rim.message;
}

// losing_in_box counts what a brute force counts: every cell [o + i eta, o + (i + 1) eta] that
// overlaps the box (by the cells' own bounds, not the quantizer), one further cell tried on every
// side, judged at its centre. An enumeration one cell short on any side differs here.
TEST(Synthesis, LosingCellsOfABoxAreCountedExactly) {
  const auto& a = agent("drone");
  auto* c = dynamic_cast<const GridController*>(a.result.controller.get());
  ASSERT_TRUE(c);
  const auto& eta = c->grid().eta();
  const auto& origin = c->grid().origin();
  const Eigen::VectorXd& x0 = a.problem.nominal.x[0];
  for (const double scale : {0.3, 0.7, 0.95}) {
    std::vector<double> lo(3), hi(3);
    for (int i = 0; i < 3; ++i) lo[i] = x0[i] - scale * a.problem.tube.eps[i], hi[i] = x0[i] + scale * a.problem.tube.eps[i];
    std::int64_t brute = 0;
    std::int64_t first[3], last[3];
    for (int d = 0; d < 3; ++d) {
      first[d] = static_cast<std::int64_t>((lo[d] - origin[d]) / eta[d]) - 2;
      last[d] = static_cast<std::int64_t>((hi[d] - origin[d]) / eta[d]) + 2;
    }
    const auto overlaps = [&](int d, std::int64_t i) {
      return origin[d] + static_cast<double>(i) * eta[d] < hi[d] && origin[d] + static_cast<double>(i + 1) * eta[d] > lo[d];
    };
    for (std::int64_t i = first[0]; i <= last[0]; ++i)
      for (std::int64_t j = first[1]; j <= last[1]; ++j)
        for (std::int64_t k = first[2]; k <= last[2]; ++k) {
          if (!overlaps(0, i) || !overlaps(1, j) || !overlaps(2, k)) continue;
          const std::int64_t idx[3] = {i, j, k};
          double centre[3];
          for (int d = 0; d < 3; ++d) centre[d] = origin[d] + (static_cast<double>(idx[d]) + 0.5) * eta[d];
          brute += c->winning(centre, 0) ? 0 : 1;
        }
    EXPECT_EQ(c->losing_in_box(lo.data(), hi.data(), 0), brute) << "scale " << scale;
    if (brute == 0) EXPECT_TRUE(c->winning(lo.data(), 0) && c->winning(hi.data(), 0));
  }
}

// The run's stop request ends the sweep where it is, on every thread count, and one that never
// fires changes nothing (the time limit of `marsyn solve` is kept to within a few columns).
TEST(Synthesis, AStopRequestEndsTheSweepAtOnce) {
  const auto p = scenarios::drone(40);
  const int T = static_cast<int>(p.nominal.x.size()) - 1;
  AbcdTracker tracker;
  for (int threads : {1, 2}) {
    TrackOptions o;
    o.threads = threads;
    int steps = 0;
    o.progress = [&](int done, int) { steps = done; };
    std::atomic<int> polls{0};
    o.stop = [&] { return ++polls > 5; };  // a few steps in (the drone has few columns a step)
    const TrackResult r = tracker.track(p, o);
    EXPECT_EQ(r.status, TrackerStatus::ResourceLimit) << threads << " thread(s): " << r.message;
    EXPECT_NE(r.message.find("stopped by the run after "), std::string::npos) << r.message;
    EXPECT_FALSE(r.controller);
    EXPECT_LT(steps, T) << "the sweep went on after the stop request";
    EXPECT_GT(polls.load(), 5);

    o.stop = [] { return false; };
    const TrackResult whole = tracker.track(p, o);
    ASSERT_EQ(whole.status, TrackerStatus::ControllerFound) << whole.message;
    EXPECT_EQ(steps, T);
  }
}
