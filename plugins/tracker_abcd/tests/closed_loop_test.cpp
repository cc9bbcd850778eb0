// Closed loop from random initial states of W_0 under every disturbance mode: the state never
// leaves the eps tube, for every example agent.
#include <gtest/gtest.h>

#include <random>

#include "agents.hpp"

using namespace marsyn;
using namespace marsyn::abcd;
using marsyn::abcd::testing::agent;

class ClosedLoop : public ::testing::TestWithParam<std::string> {};

TEST_P(ClosedLoop, NeverLeavesTheTube) {
  const auto& a = agent(GetParam());
  ASSERT_EQ(a.result.status, TrackerStatus::ControllerFound) << a.result.message;
  const auto& c = dynamic_cast<const GridController&>(*a.result.controller);
  const auto& p = a.problem;
  const int n = p.dynamics->state_dim();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int runs = 0;
  for (int start = 0; start < 4; ++start) {
    Eigen::VectorXd x0(n);
    int guard = 0;
    do {
      for (int i = 0; i < n; ++i) x0[i] = p.nominal.x[0][i] + p.tube.eps[i] * unit(rng);
    } while (!c.winning(x0.data(), 0) && ++guard < 100000);
    ASSERT_TRUE(c.winning(x0.data(), 0));
    std::vector<ClosedLoopOptions> modes;
    ClosedLoopOptions base;
    base.tau = p.tau;
    base.seed = 100 + static_cast<std::uint64_t>(start);
    modes.push_back(base);
    for (std::uint64_t v = 0; v < (1u << n); ++v) {
      auto o = base;
      o.mode = TubeDisturbance::ConstantVertex;
      o.vertex = v;
      modes.push_back(o);
    }
    for (auto m : {TubeDisturbance::UniformRandom, TubeDisturbance::VertexSwitching}) {
      auto o = base;
      o.mode = m;
      modes.push_back(o);
    }
    for (const auto& o : modes) {
      const auto r = simulate_closed_loop(*p.dynamics, c, x0, p.nominal.x, p.tube.eps, p.tube.w, o);
      ++runs;
      EXPECT_TRUE(r.in_tube()) << GetParam() << " mode " << to_string(o.mode) << " vertex " << o.vertex
                               << ": violation at " << r.first_violation << ", gave up at " << r.controller_gave_up;
      EXPECT_EQ(r.steps, static_cast<int>(p.nominal.x.size()) - 1);
    }
  }
  EXPECT_GT(runs, 10);
}

INSTANTIATE_TEST_SUITE_P(Tracker, ClosedLoop,
                         ::testing::Values("drone", "lane", "formation", "vehicle", "pendulum", "crane"));
