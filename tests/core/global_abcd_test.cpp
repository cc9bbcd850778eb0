// The global baseline's avoid test must over-approximate: a product cell containing any state
// that violates the specification must be reported unsafe.
#include <gtest/gtest.h>

#include <random>

#include "marsyn/core/tracking/global_abcd.hpp"
#include "marsyn/core/plugins/plugin_registry.hpp"
#include "marsyn/core/verification/spec_monitor.hpp"

TEST(GlobalAbcd, UnsafeCellsOverApproximateTheAvoidSet) {
  marsyn::PluginRegistry reg;
  marsyn::Problem pb;
  pb.delta = 0.5;
  for (int i = 0; i < 2; ++i) {
    marsyn::AgentSpec a;
    a.name = i ? "north" : "east";
    a.dynamics = reg.create<marsyn::Dynamics>("double_integrator");
    a.x0 = Eigen::VectorXd::Zero(2);
    a.goal = {Eigen::VectorXd::Constant(2, -9), Eigen::VectorXd::Constant(2, 9)};
    a.workspace.index = i ? std::vector<int>{-1, 0} : std::vector<int>{0, -1};
    pb.agents.push_back(a);
  }
  marsyn::Obstacle o;
  o.name = "post";
  o.vertices = {{1.5, 1.5}, {2.0, 1.5}, {2.0, 2.0}, {1.5, 2.0}};
  pb.obstacles.push_back(o);
  const auto unsafe = marsyn::product_unsafe(pb);
  const marsyn::SpecMonitor monitor(pb);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> pos(-3, 3), unit(0, 1);
  int violating_cells = 0, safe_cells = 0;
  for (int c = 0; c < 4000; ++c) {
    double lo[4], hi[4];
    for (int i = 0; i < 4; ++i) {
      lo[i] = pos(rng);
      hi[i] = lo[i] + 0.3 * unit(rng);
    }
    bool violates = false;
    for (int s = 0; s < 50 && !violates; ++s) {
      Eigen::VectorXd x(4);
      for (int i = 0; i < 4; ++i) x[i] = lo[i] + (hi[i] - lo[i]) * (s < 16 ? ((s >> (i % 4)) & 1) : unit(rng));
      violates = monitor.step(x).min() < 0;
    }
    if (violates) {
      ++violating_cells;
      EXPECT_TRUE(unsafe(lo, hi)) << "a cell with a violating state was called safe";
    } else if (!unsafe(lo, hi)) {
      ++safe_cells;
    }
  }
  EXPECT_GT(violating_cells, 100);  // the test exercises both answers
  EXPECT_GT(safe_cells, 100);
}
