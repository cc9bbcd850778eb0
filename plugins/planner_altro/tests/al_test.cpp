// The augmented Lagrangian on problems with known constrained optima, and honest failure.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "altro_solver.hpp"
#include "dynamics_double_integrator/src/double_integrator.hpp"
#include "dynamics_unicycle/src/unicycle.hpp"
#include "marsyn/core/planning/plan.hpp"
#include "marsyn/sampled_map.hpp"

using namespace marsyn;

namespace {

class AltroPlanner : public Planner {
 public:
  explicit AltroPlanner(altro::Options o) : o_(std::move(o)) {}
  std::string name() const override { return "altro"; }
  PlanResult solve(const PlanningProblem& p, const PlanOptions& r) const override { return altro::solve(p, r, o_); }
  altro::Options o_;
};

AgentSpec unicycle(const std::string& name, Eigen::Vector3d x0, Eigen::Vector3d goal) {
  AgentSpec a;
  a.name = name;
  a.dynamics = std::make_shared<models::Unicycle>();
  a.x0 = x0;
  a.state_bounds = {Eigen::Vector3d(-1, -3, -M_PI), Eigen::Vector3d(11, 3, M_PI)};
  a.input_bounds = {Eigen::Vector2d(-2, -2), Eigen::Vector2d(2, 2)};
  a.goal = {goal - Eigen::Vector3d(0.3, 0.3, 0.5), goal + Eigen::Vector3d(0.3, 0.3, 0.5)};
  a.eps = Eigen::Vector3d(0.1, 0.1, 0.1);
  return a;
}

Obstacle box(double x0, double y0, double x1, double y1) {
  Obstacle o;
  o.name = "box";
  o.vertices = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  return o;
}

}  // namespace

TEST(AugmentedLagrangian, MinimumEnergyReachIsTheKnownOptimum) {
  // min 1/2 r sum u^2  s.t.  p_T >= 1 from rest: the optimum is U* = gamma / |gamma|^2 where
  // p_T = gamma' U, with the constraint active.
  const int T = 30;
  Problem p;
  AgentSpec a;
  a.name = "car";
  a.dynamics = std::make_shared<models::DoubleIntegrator>();
  a.x0 = Eigen::Vector2d::Zero();
  a.input_bounds = {Eigen::VectorXd::Constant(1, -100), Eigen::VectorXd::Constant(1, 100)};
  a.workspace.index = {0, -1};
  p.agents.push_back(a);
  p.tau = 0.1;
  p.horizon = T;
  PlanningProblem pp;
  pp.problem = &p;
  pp.x0 = a.x0;
  pp.horizon = T;
  pp.input_bounds = a.input_bounds;
  const double inf = std::numeric_limits<double>::infinity();
  pp.state_bounds = {Eigen::Vector2d(-inf, -inf), Eigen::Vector2d(inf, inf)};
  pp.goal = {Eigen::Vector2d(1.0, -inf), Eigen::Vector2d(inf, inf)};
  altro::Options o;
  o.q_track = o.q_terminal = 0.0;
  o.r_input = 1.0;
  const auto r = altro::solve(pp, {}, o);
  ASSERT_EQ(r.status, PlannerStatus::ExactSolution) << r.message;
  EXPECT_LE(r.max_violation, 1e-6);

  double x[2] = {0, 0}, u[1] = {0}, Ar[4], Br[2];
  rk4_jacobians(*a.dynamics, x, u, p.tau, p.rk4_substeps, nullptr, Ar, Br);
  Eigen::Matrix2d A;
  A << Ar[0], Ar[1], Ar[2], Ar[3];
  Eigen::VectorXd gamma(T);
  Eigen::Matrix2d Ak = Eigen::Matrix2d::Identity();
  for (int j = T - 1; j >= 0; --j) {
    gamma[j] = (Ak * Eigen::Vector2d(Br[0], Br[1]))[0];
    Ak = A * Ak;
  }
  const Eigen::VectorXd U = gamma / gamma.squaredNorm();
  for (int k = 0; k < T; ++k) EXPECT_NEAR(r.plan.u[k][0], U[k], 1e-4) << "k = " << k;
  EXPECT_NEAR(r.plan.x[T][0], 1.0, 1e-5);
}

TEST(AugmentedLagrangian, DrivesAroundAnObstacleAndPassesTheExactCheck) {
  Problem p;
  p.agents.push_back(unicycle("car", {0, 0, 0}, {10, 0, 0}));
  p.obstacles.push_back(box(4, -0.5, 6, 0.5));
  p.delta = 0.2;
  p.tau = 0.1;
  p.horizon = 80;
  const auto out = planning::plan(p, AltroPlanner({}), {});
  ASSERT_TRUE(out.feasible) << planning::summary(p, out);
  EXPECT_GE(out.check.min_margin, 0.0);
  EXPECT_LE(out.result.max_violation, 1e-6) << out.result.message;
  EXPECT_EQ(out.result.status, PlannerStatus::ExactSolution);
  ASSERT_EQ(out.agents.size(), 1u);
  EXPECT_EQ(out.agents[0].x.size(), 81u);
  // The returned plan's states are the re-simulation of its (clamped) inputs.
  EXPECT_LE(out.check.max_state_mismatch, 1e-12);
}

TEST(AugmentedLagrangian, TwoAgentsSwapWithoutCollision) {
  Problem p;
  p.agents.push_back(unicycle("a", {0, 0, 0}, {8, 0, 0}));
  p.agents.push_back(unicycle("b", {8, 0, M_PI}, {0, 0, M_PI}));
  p.agents[1].state_bounds.lo[2] = 0;
  p.agents[1].state_bounds.hi[2] = 2 * M_PI;
  p.delta = 0.3;
  p.tau = 0.1;
  p.horizon = 80;
  const auto out = planning::plan(p, AltroPlanner({}), {});
  ASSERT_TRUE(out.feasible) << planning::summary(p, out);
}

TEST(AugmentedLagrangian, GoalInsideAnObstacleEndsWithAClearFailure) {
  Problem p;
  p.agents.push_back(unicycle("car", {0, 0, 0}, {5, 0, 0}));
  p.obstacles.push_back(box(4, -1, 6, 1));
  p.delta = 0.2;
  p.tau = 0.1;
  p.horizon = 50;
  planning::PlanSearchOptions so;
  so.max_attempts = 2;
  so.time_limit_s = 20;
  std::vector<std::string> log;
  so.log = [&](const std::string& line) { log.push_back(line); };
  const auto out = planning::plan(p, AltroPlanner({}), so);
  EXPECT_FALSE(out.feasible);
  // The horizon search tried a longer horizon and logged both attempts.
  ASSERT_EQ(out.attempts.size(), 2u);
  EXPECT_GT(out.attempts[1].horizon, out.attempts[0].horizon);
  ASSERT_EQ(log.size(), 2u);
  EXPECT_NE(log[0].find("T = 50"), std::string::npos) << log[0];
  EXPECT_NE(planning::summary(p, out).find("NO FEASIBLE PLAN"), std::string::npos);
  const auto st = out.attempts.back().status;
  EXPECT_TRUE(st == PlannerStatus::Infeasible || st == PlannerStatus::ApproximateSolution) << to_string(st);
  EXPECT_NE(out.result.message.find("violated"), std::string::npos) << out.result.message;
  EXPECT_LT(out.total_time_s, 20.0);
  EXPECT_FALSE(out.check.passed);
}

TEST(AugmentedLagrangian, TimeLimitEndsWithTimeoutStatus) {
  Problem p;
  p.agents.push_back(unicycle("car", {0, 0, 0}, {10, 0, 0}));
  p.obstacles.push_back(box(4, -0.5, 6, 0.5));
  p.delta = 0.2;
  p.horizon = 80;
  const auto pp = planning::assemble(p, 80);
  PlanOptions run;
  run.time_limit_s = 0.0;
  const auto r = altro::solve(pp, run, {});
  EXPECT_EQ(r.status, PlannerStatus::Timeout) << r.message;
  EXPECT_EQ(r.plan.u.size(), 80u);  // the best plan so far comes back all the same
}
