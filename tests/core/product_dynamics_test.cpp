#include <gtest/gtest.h>

#include "dynamics_checks.hpp"
#include "marsyn/core/plugins/plugin_registry.hpp"
#include "marsyn/core/tracking/product_dynamics.hpp"

TEST(ProductDynamics, StacksTheAgentsFields) {
  marsyn::PluginRegistry reg;
  std::vector<marsyn::AgentSpec> agents(2);
  agents[0].name = "crane";
  agents[0].dynamics = reg.create<marsyn::Dynamics>("cartpole");
  agents[1].name = "car";
  agents[1].dynamics = reg.create<marsyn::Dynamics>("double_integrator");
  marsyn::ProductDynamics p(agents);
  ASSERT_EQ(p.state_dim(), 6);
  ASSERT_EQ(p.input_dim(), 2);
  EXPECT_EQ(p.state_names()[4], "car.p");
  const double x[6] = {0, 0.3, 1.0, 0.2, 5, -1}, u[2] = {2, 0.5};
  double dx[6], a[4], b[2];
  p.field(x, u, dx);
  agents[0].dynamics->field(x, u, a);
  agents[1].dynamics->field(x + 4, u + 1, b);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(dx[i], a[i]);
  for (int i = 0; i < 2; ++i) EXPECT_EQ(dx[4 + i], b[i]);
  const marsyn::testing::SampleBox where{{-0.2, -2, 1.2, -5, 3, -3, -7, -3}, {5.5, 4, 4.7, 5, 9, 2, 7, 3}};
  marsyn::testing::expect_ad_matches_finite_differences(p, where, 50);
  marsyn::testing::expect_interval_encloses_points(p, where, 50, 50);
  marsyn::testing::expect_declared_independence(p, where);
}
