// The built plugin library: one manifest entry "altro" of kind planner, typed parameters, and
// ParamError for bad values.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <memory>

#include "marsyn/plugin.hpp"

namespace {

const marsyn_plugin_manifest* manifest() {
  static void* lib = dlopen(MARSYN_ALTRO_LIBRARY, RTLD_NOW | RTLD_LOCAL);
  if (!lib) return nullptr;
  auto entry = reinterpret_cast<const marsyn_plugin_manifest* (*)()>(dlsym(lib, "marsyn_plugin_entry_point"));
  return entry ? entry() : nullptr;
}

}  // namespace

TEST(Plugin, ManifestDeclaresTheAltroPlanner) {
  const auto* m = manifest();
  ASSERT_NE(m, nullptr) << dlerror();
  EXPECT_EQ(m->api_version, MARSYN_PLUGIN_API_VERSION);
  ASSERT_EQ(m->entry_count, 1u);
  EXPECT_STREQ(m->entries[0].kind, "planner");
  EXPECT_STREQ(m->entries[0].name, "altro");
  const auto specs = m->entries[0].param_specs();
  bool has_coupling = false;
  for (const auto& s : specs) has_coupling |= s.name == "coupling" && s.type == marsyn::ParamType::String;
  EXPECT_TRUE(has_coupling);
  std::unique_ptr<marsyn::Planner> p(static_cast<marsyn::Planner*>(m->entries[0].create({})));
  EXPECT_EQ(p->name(), "altro");
}

TEST(Plugin, BadParametersThrowParamError) {
  const auto* m = manifest();
  ASSERT_NE(m, nullptr);
  marsyn::Params bad;
  bad.set("coupling", std::string("diagonal"));
  try {
    delete static_cast<marsyn::Planner*>(m->entries[0].create(bad));
    FAIL() << "accepted coupling = diagonal";
  } catch (const marsyn::ParamError& e) {
    EXPECT_EQ(e.field(), "coupling");
  }
  marsyn::Params neg;
  neg.set("penalty_scaling", 0.5);
  EXPECT_THROW(delete static_cast<marsyn::Planner*>(m->entries[0].create(neg)), marsyn::ParamError);
}

TEST(Plugin, SolveOnAnEmptyProblemIsInvalidInputNotAnException) {
  const auto* m = manifest();
  ASSERT_NE(m, nullptr);
  std::unique_ptr<marsyn::Planner> p(static_cast<marsyn::Planner*>(m->entries[0].create({})));
  const auto r = p->solve(marsyn::PlanningProblem{}, {});
  EXPECT_EQ(r.status, marsyn::PlannerStatus::InvalidInput);
  EXPECT_FALSE(r.message.empty());
}
