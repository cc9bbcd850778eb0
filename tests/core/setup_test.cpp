// The front door (setup.hpp) is the path every front end takes: its plan and track of the
// pendulum, with a warm-start chain (planner.warm_start), give the plan the stage functions give
// when called by hand and the plan and controller files `marsyn plan` and `marsyn track` write,
// bit for bit (timing fields aside).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "marsyn/core/planning/plan_io.hpp"
#include "marsyn/core/setup.hpp"
#include "pendulum_variant.hpp"

namespace {

namespace fs = std::filesystem;

std::string bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// plan.json without its timing fields, which differ between any two runs.
nlohmann::json untimed(nlohmann::json j) {
  if (j.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (auto it = j.begin(); it != j.end(); ++it)
      if (it.key().find("time_s") == std::string::npos) out[it.key()] = untimed(it.value());
    return out;
  }
  if (j.is_array())
    for (auto& v : j) v = untimed(v);
  return j;
}

nlohmann::json read_json(const fs::path& p) { return nlohmann::json::parse(bytes(p)); }

const marsyn::planning::PlanOutcome& checked(const marsyn::planning::PlanOutcome& o) {
  EXPECT_TRUE(o.feasible) << o.check.message;
  return o;
}

TEST(Setup, PlanAndTrackAreTheCommandLines) {
  const std::string yaml = marsyn::test::pendulum_variant("setup_chain", "tracker: abcd",
                                                          {{"planner: altro\n", "planner: {name: altro, warm_start: altro}\n"}});
  const fs::path dir = fs::path(yaml).parent_path() / "setup_test";
  fs::remove_all(dir);
  fs::create_directories(dir);

  marsyn::Setup setup(marsyn::load_problem(yaml));
  ASSERT_EQ(setup.problem().warm_start_planner.name, "altro");
  const marsyn::planning::PlanOutcome plan = checked(setup.plan());

  // The stage functions by hand: the planner chained after its warm-start planner.
  const auto& lp = setup.loaded();
  const auto main = lp.registry->create<marsyn::Planner>("altro", lp.problem.planner.params);
  const auto warm = lp.registry->create<marsyn::Planner>("altro", lp.problem.warm_start_planner.params);
  marsyn::planning::PlanSearchOptions chained;
  chained.warm_start_planner = warm.get();
  const marsyn::planning::PlanOutcome by_hand = checked(marsyn::planning::plan(lp.problem, *main, chained));
  ASSERT_EQ(plan.attempts.size(), by_hand.attempts.size());
  EXPECT_EQ(plan.plan.u, by_hand.plan.u);
  EXPECT_EQ(plan.plan.x, by_hand.plan.x);

  // The command lines, in another process: `marsyn track` without --plan plans first.
  const std::string exe = MARSYN_EXE;
  const std::string cli = (dir / "cli").string();
  ASSERT_EQ(std::system((exe + " plan " + yaml + " --out " + cli + " > /dev/null 2>&1").c_str()), 0);
  ASSERT_EQ(std::system((exe + " track " + yaml + " --agent pendulum --out " + cli + " > /dev/null 2>&1").c_str()), 0);

  marsyn::planning::write_plan_json((dir / "plan.json").string(), setup.problem(), plan);
  EXPECT_EQ(untimed(read_json(dir / "plan.json")), untimed(read_json(fs::path(cli) / "plan.json")));

  const marsyn::FallbackTrack t = setup.track(0, plan.nominal.at(0), {}, {});
  ASSERT_EQ(t.result.status, marsyn::TrackerStatus::ControllerFound) << t.result.message;
  EXPECT_EQ(t.tracker, "abcd");
  ASSERT_TRUE(t.result.controller);
  t.result.controller->write((dir / "pendulum.ctrl").string());
  const std::string mine = bytes(dir / "pendulum.ctrl");
  EXPECT_FALSE(mine.empty());
  EXPECT_TRUE(mine == bytes(fs::path(cli) / "pendulum.ctrl")) << "the controller files differ";
}

}  // namespace
