// The OMPL planner through core's horizon search and exact robust check, with a time limit.
#include <gtest/gtest.h>

#include "marsyn/core/planning/plan.hpp"
#include "ompl_solver.hpp"
#include "test_problems.hpp"

using namespace marsyn;

namespace {

class OmplPlanner : public Planner {
 public:
  explicit OmplPlanner(ompl_planner::Options o) : o_(std::move(o)) {}
  std::string name() const override { return "ompl"; }
  PlanResult solve(const PlanningProblem& p, const PlanOptions& r) const override { return ompl_planner::solve(p, r, o_); }
  ompl_planner::Options o_;
};

ompl_planner::Options options(const std::string& planner, double limit) {
  ompl_planner::Options o;
  o.planner = planner;
  o.time_limit_s = limit;
  o.seed = 1;
  return o;
}

planning::PlanOutcome run(const Problem& p, const ompl_planner::Options& o) {
  OmplPlanner planner(o);
  planning::PlanSearchOptions so;
  so.max_attempts = 1;
  so.time_limit_s = 60;
  auto out = planning::plan(p, planner, so);
  std::cout << planning::summary(p, out) << "  planner: " << out.result.message << "\n";
  return out;
}

}  // namespace

TEST(OmplPlanner, SstDrivesAUnicycleAroundABox) {
  const auto out = run(testproblems::unicycle_obstacle(60), options("sst", 10));
  EXPECT_TRUE(out.feasible) << out.check.message << " / " << out.result.message;
  EXPECT_EQ(out.result.status, PlannerStatus::ExactSolution);
}

TEST(OmplPlanner, RrtDrivesAUnicycleAroundABox) {
  const auto out = run(testproblems::unicycle_obstacle(60), options("rrt", 10));
  EXPECT_TRUE(out.feasible) << out.check.message << " / " << out.result.message;
}

TEST(OmplPlanner, SstSwingsThePendulumUpAndHoldsIt) {
  const auto out = run(testproblems::pendulum_problem(100), options("sst", 10));
  EXPECT_TRUE(out.feasible) << out.check.message << " / " << out.result.message;
}

TEST(OmplPlanner, ATooShortHorizonIsATimeoutNotASuccess) {
  const auto out = run(testproblems::pendulum_problem(10), options("sst", 1));
  EXPECT_FALSE(out.feasible);
  EXPECT_NE(out.result.status, PlannerStatus::ExactSolution);
}

TEST(OmplPlanner, Kpiece1DrivesAUnicycleAroundABox) {
  const auto out = run(testproblems::unicycle_obstacle(60), options("kpiece1", 10));
  EXPECT_TRUE(out.feasible) << out.check.message << " / " << out.result.message;
}


TEST(OmplPlanner, NothingIsRequiredOfTheFixedStart) {
  // x0 outside the shrunk state bounds: like the other planners, OMPL must not refuse it.
  auto p = testproblems::pendulum_problem(100);
  p.agents[0].x0 = Eigen::Vector2d(-2.4, 0.0);
  auto pp = planning::assemble(p, p.horizon);
  const auto r = ompl_planner::solve(pp, {}, options("sst", 1));
  EXPECT_NE(r.status, PlannerStatus::InvalidInput) << r.message;
}

TEST(OmplPlanner, RejectsBadParameters) {
  Params p;
  p.set("planner", std::string("prm"));
  EXPECT_THROW(ompl_planner::Options::from(p), ParamError);
  Params q;
  q.set("time_weight", 0.0);
  EXPECT_THROW(ompl_planner::Options::from(q), ParamError);
}

// A mission stage (ConstraintStage::AtSteps) reaches OMPL's validity checker at the knot given by
// a state's elapsed time: SST finds a path through the region at its knot.
TEST(OmplPlanner, SstVisitsAMissionStageAtItsKnot) {
  Problem p = testproblems::unicycle_mission();
  p.agents[0].stages.resize(1);
  const auto out = run(p, options("sst", 15));
  EXPECT_TRUE(out.feasible) << out.check.message;
  ASSERT_EQ(out.check.stages.size(), 1u);
  EXPECT_GE(out.check.stages[0].margin, 0.0) << out.check.stages[0].name;
}
