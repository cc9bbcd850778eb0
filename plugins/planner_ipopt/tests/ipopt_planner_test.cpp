// The Ipopt planner through core's horizon search and exact robust check.
#include <gtest/gtest.h>

#include <thread>

#include "ipopt_solver.hpp"
#include "marsyn/core/planning/plan.hpp"
#include "test_problems.hpp"

using namespace marsyn;

namespace {

class IpoptPlanner : public Planner {
 public:
  explicit IpoptPlanner(ipopt_planner::Options o) : o_(std::move(o)) {}
  std::string name() const override { return "ipopt"; }
  PlanResult solve(const PlanningProblem& p, const PlanOptions& r) const override { return ipopt_planner::solve(p, r, o_); }
  ipopt_planner::Options o_;
};

planning::PlanOutcome run(const Problem& p, const ipopt_planner::Options& o) {
  IpoptPlanner planner(o);
  planning::PlanSearchOptions so;
  so.max_attempts = 1;
  so.time_limit_s = 30;
  return planning::plan(p, planner, so);
}

}  // namespace

TEST(IpoptPlanner, SwingsThePendulumUp) {
  const auto out = run(testproblems::pendulum_problem(), {});
  std::cout << planning::summary(testproblems::pendulum_problem(), out) << out.result.message << "\n";
  EXPECT_TRUE(out.feasible) << out.check.message << " / " << out.result.message;
  EXPECT_EQ(out.result.status, PlannerStatus::ExactSolution) << out.result.message;
  // Ipopt's status in words, not its number (issue 54: "ipopt status 2").
  EXPECT_EQ(out.result.message.rfind("Ipopt: solved", 0), 0u) << out.result.message;
  EXPECT_EQ(out.result.message.find("status"), std::string::npos) << out.result.message;
}

TEST(IpoptPlanner, TwoUnicyclesPassEachOther) {
  const auto p = testproblems::unicycle_crossing(60, true);
  const auto out = run(p, {});
  std::cout << planning::summary(p, out) << out.result.message << "\n";
  EXPECT_TRUE(out.feasible) << out.check.message << " / " << out.result.message;
}

TEST(IpoptPlanner, LimitedMemoryHessianAlsoSolvesThePendulum) {
  ipopt_planner::Options o;
  o.hessian = "limited-memory";
  const auto out = run(testproblems::pendulum_problem(), o);
  std::cout << out.result.message << ", " << out.result.iterations << " iterations\n";
  EXPECT_TRUE(out.feasible) << out.check.message << " / " << out.result.message;
}

TEST(IpoptPlanner, WarmStartFromAFeasiblePlanConvergesQuickly) {
  const auto p = testproblems::pendulum_problem();
  const auto cold = run(p, {});
  ASSERT_TRUE(cold.feasible);
  auto pp = planning::assemble(p, p.horizon);
  pp.warm_start = cold.plan;
  const auto warm = ipopt_planner::solve(pp, {}, {});
  EXPECT_EQ(warm.status, PlannerStatus::ExactSolution) << warm.message;
  EXPECT_LE(warm.iterations, cold.result.iterations);
}

TEST(IpoptPlanner, AnUnreachableGoalIsNotReportedAsExact) {
  const auto out = run(testproblems::pendulum_problem(10), {});
  EXPECT_FALSE(out.feasible);
  EXPECT_NE(out.result.status, PlannerStatus::ExactSolution) << out.result.message;
}

TEST(IpoptPlanner, ConcurrentSolvesAreSerializedAndBothSucceed) {
  const auto p = testproblems::pendulum_problem();
  planning::PlanOutcome a, b;
  std::thread t1([&] { a = run(p, {}); });
  std::thread t2([&] { b = run(p, {}); });
  t1.join();
  t2.join();
  EXPECT_TRUE(a.feasible);
  EXPECT_TRUE(b.feasible);
}

TEST(IpoptPlanner, RejectsBadParameters) {
  Params p;
  p.set("hessian", std::string("newton"));
  EXPECT_THROW(ipopt_planner::Options::from(p), ParamError);
}

// Mission stages (ConstraintStage::AtSteps) reach the planner: both regions visited at their
// knots, in order, robustly.
TEST(IpoptPlanner, VisitsTheMissionStagesAtTheirKnots) {
  const auto p = testproblems::unicycle_mission();
  const auto out = run(p, {});
  EXPECT_TRUE(out.feasible) << out.check.message << " / " << out.result.message;
  ASSERT_EQ(out.check.stages.size(), 2u);
  for (const auto& v : out.check.stages) EXPECT_GE(v.margin, 0.0) << v.name << " at step " << v.step;
  EXPECT_LT(out.check.stages[0].step, out.check.stages[1].step);
}
