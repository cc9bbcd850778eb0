// The NLopt planner through core's horizon search and exact robust check: success means the
// check passed, never the solver's own status alone.
#include <gtest/gtest.h>

#include "marsyn/core/planning/plan.hpp"
#include "nlopt_solver.hpp"
#include "test_problems.hpp"

using namespace marsyn;

namespace {

class NloptPlanner : public Planner {
 public:
  explicit NloptPlanner(nlopt_planner::Options o) : o_(std::move(o)) {}
  std::string name() const override { return "nlopt"; }
  PlanResult solve(const PlanningProblem& p, const PlanOptions& r) const override { return nlopt_planner::solve(p, r, o_); }
  nlopt_planner::Options o_;
};

planning::PlanOutcome run(const Problem& p, const nlopt_planner::Options& o, int attempts = 1) {
  NloptPlanner planner(o);
  planning::PlanSearchOptions so;
  so.max_attempts = attempts;
  so.time_limit_s = 30;
  return planning::plan(p, planner, so);
}

}  // namespace

TEST(NloptPlanner, SwingsThePendulumUp) {
  const auto out = run(testproblems::pendulum_problem(), {});
  EXPECT_TRUE(out.feasible) << out.check.message << " / " << out.result.message;
  EXPECT_EQ(out.result.status, PlannerStatus::ExactSolution) << out.result.message;
  EXPECT_GT(out.check.min_margin, 0.0);
}

TEST(NloptPlanner, TwoUnicyclesPassEachOther) {
  const auto out = run(testproblems::unicycle_crossing(), {});
  EXPECT_TRUE(out.feasible) << out.check.message << " / " << out.result.message;
  EXPECT_GT(out.check.min_margin, 0.0);
}

TEST(NloptPlanner, SlsqpAlsoSolvesThePendulum) {
  nlopt_planner::Options o;
  o.algorithm = "slsqp";
  const auto out = run(testproblems::pendulum_problem(), o);
  EXPECT_TRUE(out.feasible) << out.check.message << " / " << out.result.message;
}

TEST(NloptPlanner, AnUnreachableGoalIsNotReportedAsExact) {
  // 1 s is too short to swing up with |u| <= 3: the answer must not claim success.
  const auto out = run(testproblems::pendulum_problem(10), {});
  EXPECT_FALSE(out.feasible);
  EXPECT_NE(out.result.status, PlannerStatus::ExactSolution);
}

TEST(NloptPlanner, RefusesProblemsTooLargeForDenseShooting) {
  nlopt_planner::Options o;
  o.max_dense_entries = 100;
  const auto out = run(testproblems::pendulum_problem(), o);
  EXPECT_EQ(out.result.status, PlannerStatus::InvalidInput);
  EXPECT_FALSE(out.feasible);
}

TEST(NloptPlanner, ExactStatusAgreesWithTheExactCheck) {
  for (const auto& p : {testproblems::pendulum_problem(), testproblems::unicycle_crossing(), testproblems::pendulum_problem(10)}) {
    const auto out = run(p, {});
    EXPECT_EQ(out.result.status == PlannerStatus::ExactSolution, out.feasible) << p.name;
    std::cout << p.name << ": " << planning::summary(p, out) << "  planner: " << out.result.message << ", cost "
              << out.result.cost << ", iterations " << out.result.iterations << "\n";
  }
}

TEST(NloptPlanner, RejectsBadParameters) {
  Params p;
  p.set("algorithm", std::string("cobyla"));
  EXPECT_THROW(nlopt_planner::Options::from(p), ParamError);
}

// Mission stages (ConstraintStage::AtSteps) reach the planner: both regions visited at their
// knots, in order, robustly.
TEST(NloptPlanner, VisitsTheMissionStagesAtTheirKnots) {
  const auto p = testproblems::unicycle_mission();
  const auto out = run(p, {});
  EXPECT_TRUE(out.feasible) << out.check.message << " / " << out.result.message;
  ASSERT_EQ(out.check.stages.size(), 2u);
  for (const auto& v : out.check.stages) EXPECT_GE(v.margin, 0.0) << v.name << " at step " << v.step;
  EXPECT_LT(out.check.stages[0].step, out.check.stages[1].step);
}
