// The built MODULE loads through the C entry point, creates the tracker from typed parameters,
// rejects bad ones, and tracks, writes and reads back a controller: what the registry will do.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include "marsyn/plugin.hpp"
#include "track_scenarios.hpp"

using namespace marsyn;

TEST(Plugin, LoadsCreatesTracksAndReads) {
  void* h = dlopen(MARSYN_TRACKER_ABCD_MODULE, RTLD_NOW | RTLD_LOCAL);
  ASSERT_TRUE(h) << dlerror();
  using EntryFn = const marsyn_plugin_manifest* (*)();
  auto entry = reinterpret_cast<EntryFn>(dlsym(h, "marsyn_plugin_entry_point"));
  ASSERT_TRUE(entry);
  const marsyn_plugin_manifest* m = entry();
  EXPECT_EQ(m->api_version, MARSYN_PLUGIN_API_VERSION);
  ASSERT_EQ(m->entry_count, 1u);
  EXPECT_STREQ(m->entries[0].kind, "tracker");
  EXPECT_STREQ(m->entries[0].name, "abcd");
  const auto specs = m->entries[0].param_specs();
  EXPECT_GE(specs.size(), 5u);

  Params bad;
  bad.set("taylor_terms", 40L);
  EXPECT_THROW(m->entries[0].create(bad), ParamError);

  Params p;
  p.set("substeps", 3L);
  p.set("threads", 2L);
  std::unique_ptr<Tracker> t(static_cast<Tracker*>(m->entries[0].create(p)));
  EXPECT_EQ(t->name(), "abcd");
  const auto problem = abcd::scenarios::vehicle();
  const TrackResult r = t->track(problem, TrackOptions{});
  ASSERT_EQ(r.status, TrackerStatus::ControllerFound) << r.message;
  const std::string path = ::testing::TempDir() + "/plugin_vehicle.ctl";
  r.controller->write(path);
  auto back = t->read_controller(path);
  double u1[1], u2[1];
  EXPECT_EQ(back->input(problem.nominal.x[0].data(), 0, u1), ControlStatus::Ok);
  EXPECT_EQ(r.controller->input(problem.nominal.x[0].data(), 0, u2), ControlStatus::Ok);
  EXPECT_EQ(u1[0], u2[0]);
  back.reset();
  t.reset();
  // Objects created by the library are gone before it is unloaded.
  EXPECT_EQ(dlclose(h), 0);
}
