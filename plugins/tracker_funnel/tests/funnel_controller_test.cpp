#include <dlfcn.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "funnel_scenarios.hpp"
#include "funnel_tracker.hpp"
#include "marsyn/plugin.hpp"

namespace marsyn::funnel {
namespace {

std::shared_ptr<const FunnelController> unicycle_controller() {
  static const auto c = [] {
    const TrackResult r = FunnelTracker().track(testing::unicycle(30), {});
    EXPECT_EQ(r.status, TrackerStatus::ControllerFound) << r.message;
    return std::dynamic_pointer_cast<const FunnelController>(r.controller);
  }();
  return c;
}

std::string temp_file(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("marsyn_funnel_" + std::to_string(::getpid()) + "_" + name)).string();
}

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

TEST(FunnelController, FileRoundTripIsByteIdenticalAndAnswersAlike) {
  const auto c = unicycle_controller();
  ASSERT_TRUE(c);
  const std::string a = temp_file("a.ctl"), b = temp_file("b.ctl");
  c->write(a);
  const auto back = FunnelTracker().read_controller(a);
  back->write(b);
  EXPECT_EQ(slurp(a), slurp(b));
  // Small: nominal, gains and an order-8 zonotope (n x 8n, 576 bytes here) per step, 46.6 KB.
  EXPECT_LT(slurp(a).size(), 50'000u);
  const FunnelData& d = c->data();
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int s = 0; s < 2000; ++s) {
    const int k = s % d.horizon();
    std::vector<double> x(3), u1(2), u2(2);
    for (int i = 0; i < 3; ++i) x[i] = d.x_nom[k][i] + 1.2 * d.eps[i] * U(rng);
    const ControlStatus s1 = c->input(x.data(), k, u1.data()), s2 = back->input(x.data(), k, u2.data());
    ASSERT_EQ(s1, s2);
    if (s1 == ControlStatus::Ok) EXPECT_EQ(u1, u2);
  }
  EXPECT_EQ(back->period_enclosures().size(), c->period_enclosures().size());
  std::filesystem::remove(a);
  std::filesystem::remove(b);
}

TEST(FunnelController, StatusesOutsideTheSetAndTheHorizon) {
  const auto c = unicycle_controller();
  ASSERT_TRUE(c);
  const FunnelData& d = c->data();
  double u[2];
  EXPECT_EQ(c->input(d.x_nom[0].data(), 0, u), ControlStatus::Ok);
  EXPECT_EQ(c->input(d.x_nom[0].data(), -1, u), ControlStatus::OutsideHorizon);
  EXPECT_EQ(c->input(d.x_nom[0].data(), d.horizon(), u), ControlStatus::OutsideHorizon);
  std::vector<double> far = d.x_nom[3];
  far[0] += 2 * d.eps[0];
  EXPECT_EQ(c->input(far.data(), 3, u), ControlStatus::OutsideDomain);
  std::vector<double> nan = d.x_nom[3];
  nan[1] = std::nan("");
  EXPECT_EQ(c->input(nan.data(), 3, u), ControlStatus::OutsideDomain);
  // At the nominal the input is the nominal input.
  EXPECT_EQ(c->input(d.x_nom[5].data(), 5, u), ControlStatus::Ok);
  EXPECT_DOUBLE_EQ(u[0], d.u_nom[5][0]);
  EXPECT_DOUBLE_EQ(u[1], d.u_nom[5][1]);
}

TEST(FunnelController, CorruptFilesAreRefusedWithTheReason) {
  const auto c = unicycle_controller();
  ASSERT_TRUE(c);
  const std::string good = serialize(c->data());
  auto refused = [](const std::string& bytes) -> std::string {
    try {
      deserialize(bytes, "x.ctl");
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  };
  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  EXPECT_NE(refused(flipped).find("checksum"), std::string::npos);
  EXPECT_NE(refused(good.substr(0, good.size() - 3)).find("size"), std::string::npos);
  std::string magic = good;
  magic[6] = 'C';  // an abcd controller's magic
  EXPECT_NE(refused(magic).find("not a marsyn funnel controller"), std::string::npos);
  EXPECT_NE(refused("").find("bad magic"), std::string::npos);
  EXPECT_EQ(refused(good), "");
}

TEST(FunnelController, PluginLibraryHasOneTrackerEntry) {
  void* lib = dlopen(MARSYN_TRACKER_FUNNEL_MODULE, RTLD_NOW | RTLD_LOCAL);
  ASSERT_TRUE(lib) << dlerror();
  auto entry = reinterpret_cast<const marsyn_plugin_manifest* (*)()>(dlsym(lib, "marsyn_plugin_entry_point"));
  ASSERT_TRUE(entry);
  const marsyn_plugin_manifest* m = entry();
  EXPECT_EQ(m->api_version, MARSYN_PLUGIN_API_VERSION);
  ASSERT_EQ(m->entry_count, 1u);
  EXPECT_STREQ(m->entries[0].kind, "tracker");
  EXPECT_STREQ(m->entries[0].name, "funnel");
  Params bad;
  bad.set("substeps", 12L);  // not a multiple of 8
  EXPECT_THROW(m->entries[0].create(bad), ParamError);
  auto* t = static_cast<Tracker*>(m->entries[0].create(Params{}));
  EXPECT_EQ(t->name(), "funnel");
  delete t;
  // The library stays loaded: the tracker's vtable lives in it.
}

}  // namespace
}  // namespace marsyn::funnel
