#include <gtest/gtest.h>

#include "marsyn/core/plugins/plugin_registry.hpp"

using marsyn::PluginRegistry;

TEST(PluginRegistry, FindsTheBuiltInDynamics) {
  PluginRegistry reg;
  EXPECT_NE(reg.find("dynamics", "unicycle"), nullptr);
  EXPECT_NE(reg.find("dynamics", "cartpole"), nullptr);
  EXPECT_EQ(reg.find("dynamics", "no_such_model"), nullptr);
  EXPECT_THROW(reg.create<marsyn::Dynamics>("no_such_model"), std::out_of_range);
}

TEST(PluginRegistry, ObjectsKeepTheirLibraryLoaded) {
  std::shared_ptr<marsyn::Dynamics> dyn;
  {
    PluginRegistry reg;
    dyn = reg.create<marsyn::Dynamics>("unicycle");
  }  // the registry is gone; the object's vtable must still be mapped
  const double x[3] = {0, 0, 0}, u[2] = {1, 0};
  double dx[3];
  dyn->field(x, u, dx);
  EXPECT_DOUBLE_EQ(dx[0], 1.0);
  EXPECT_EQ(dyn->type(), "unicycle");
}

TEST(PluginRegistry, ParametersReachTheModelAndAreValidated) {
  PluginRegistry reg;
  marsyn::Params p;
  p.set("input_gain", 0.5);
  auto pend = reg.create<marsyn::Dynamics>("pendulum", p);
  const double x[2] = {0, 0}, u[1] = {2};
  double dx[2];
  pend->field(x, u, dx);
  EXPECT_DOUBLE_EQ(dx[1], 1.0);
  p.set("input_gain", -1.0);
  EXPECT_THROW(reg.create<marsyn::Dynamics>("pendulum", p), marsyn::ParamError);
}

TEST(PluginRegistry, RefusesALibraryOfAnotherApiVersion) {
  PluginRegistry reg({OTHER_API_PLUGIN_DIR});
  bool refused = false;
  for (const auto& p : reg.problems())
    refused = refused || (p.explicit_path && p.reason.find("API version 999") != std::string::npos);
  EXPECT_TRUE(refused);
}
