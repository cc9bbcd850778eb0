// Requirements between the samples inside the planning problem (continuous guarantee): a plan
// whose knots alone are constrained cuts the corner of an obstacle between two knots; with the
// interior points of every period in the problem, the first solve passes the exact continuous
// check.
#include <gtest/gtest.h>

#include <cmath>

#include "altro_solver.hpp"
#include "marsyn/sampled_map.hpp"
#include "rk4.hpp"
#include "marsyn/core/planning/plan.hpp"
#include "test_problems.hpp"

using namespace marsyn;

namespace {

class Altro final : public Planner {
 public:
  std::string name() const override { return "altro"; }
  PlanResult solve(const PlanningProblem& p, const PlanOptions& r) const override { return altro::solve(p, r, o_); }
  altro::Options o_ = altro::Options::from({});
};

// One unicycle along the diagonal of the field past the corner of a box: the shortest way hugs
// the (grown) corner, where a chord between two knots cuts in.
Problem corner(int horizon) {
  Problem p = testproblems::unicycle_obstacle(horizon);
  auto& a = p.agents[0];
  a.x0 = Eigen::Vector3d(0, 0, M_PI / 4);
  a.state_bounds = {Eigen::Vector3d(-1, -1, -2 * M_PI), Eigen::Vector3d(7, 7, 2 * M_PI)};
  const Eigen::Vector3d goal(6, 6, M_PI / 4), r(0.4, 0.4, 10.0);
  a.goal = {goal - r, goal + r};
  p.obstacles[0].vertices = {{2.0, 3.3}, {3.2, 3.3}, {3.2, 4.5}, {2.0, 4.5}};
  p.guarantee = Guarantee::Continuous;
  return p;
}

}  // namespace

TEST(BetweenSamples, KnotsAloneCutTheCorner) {
  const Problem p = corner(45);
  planning::PlanSearchOptions o;
  o.assembly.between_points = 0;  // the sampled requirements only
  o.max_attempts = 1;
  const auto out = planning::plan(p, Altro(), o);
  ASSERT_FALSE(out.attempts.empty());
  const auto& c = out.attempts.front().check;
  EXPECT_GE(c.sampled_margin, 0.0) << c.message;
  EXPECT_LT(c.between_margin, 0.0) << c.message;  // robust at the knots, not between them
}

TEST(BetweenSamples, OneSolvePassesTheContinuousCheck) {
  const Problem p = corner(45);
  planning::PlanSearchOptions o;
  o.max_attempts = 1;
  const auto out = planning::plan(p, Altro(), o);
  ASSERT_EQ(out.attempts.size(), 1u) << out.check.message;  // no re-plan after the fact
  EXPECT_TRUE(out.feasible) << out.check.message;
  EXPECT_TRUE(out.check.continuous);
  EXPECT_GE(out.check.between_margin, 0.0) << out.check.message;
  EXPECT_LE(out.result.max_violation, 1e-6) << out.result.message;  // the solver met the rows
}

namespace {

// N unicycles swapping across a circle of radius 3: most pairs are far apart at most knots.
Problem swap_team(int horizon, int N = 8) {
  Problem p = testproblems::unicycle_crossing(horizon);
  const AgentSpec proto = p.agents[0];
  p.agents.clear();
  for (int i = 0; i < N; ++i) {
    AgentSpec a = proto;
    const double t = 2 * M_PI * i / N, h = std::atan2(-std::sin(t), -std::cos(t));
    a.name = "u" + std::to_string(i);
    a.x0 = Eigen::Vector3d(3 * std::cos(t), 3 * std::sin(t), h);
    a.state_bounds = {Eigen::Vector3d(-4.5, -4.5, -7), Eigen::Vector3d(4.5, 4.5, 7)};
    const Eigen::Vector3d g(-a.x0[0], -a.x0[1], h), r(0.3, 0.3, 0.8);
    a.goal = {g - r, g + r};
    a.tube.eps = Eigen::Vector3d(0.1, 0.1, 0.1);
    p.agents.push_back(a);
  }
  p.delta = 0.2;
  p.guarantee = Guarantee::Continuous;
  return p;
}

}  // namespace

// The broad phase skips only rows that would add exactly zero: the plan is the same bit for bit,
// with and without it, under both guarantees and both norms.
TEST(BetweenSamples, BroadPhaseLeavesThePlanUnchanged) {
  for (Guarantee g : {Guarantee::Continuous, Guarantee::Sampled})
    for (Norm norm : {Norm::Inf, Norm::Two}) {
      Problem p = swap_team(50);
      p.guarantee = g;
      p.delta_norm = norm;
      const auto pp = planning::assemble(p, p.horizon);
      PlanOptions run;
      altro::Options on = altro::Options::from({}), off = on;
      off.broad_phase = false;
      const PlanResult a = altro::solve(pp, run, on), b = altro::solve(pp, run, off);
      ASSERT_EQ(a.plan.u.size(), b.plan.u.size());
      EXPECT_EQ(a.iterations, b.iterations);
      EXPECT_EQ(a.max_violation, b.max_violation);
      for (size_t k = 0; k < a.plan.u.size(); ++k) ASSERT_EQ(a.plan.u[k], b.plan.u[k]) << "step " << k;
      EXPECT_LT(a.max_violation, 1e-3) << a.message;
    }
}

// A swap whose bent references still meet in the middle: the search bends them further (a
// roundabout), which the message says, and the solve needs fewer iterations than from the
// references that meet.
TEST(BetweenSamples, BendSearchOpensARoundabout) {
  Problem p = swap_team(60, 14);
  p.guarantee = Guarantee::Sampled;
  const auto pp = planning::assemble(p, p.horizon);
  altro::Options on = altro::Options::from({}), off = on;
  on.coupling = off.coupling = "block";
  off.bend_search = false;
  const PlanResult a = altro::solve(pp, PlanOptions{}, on), b = altro::solve(pp, PlanOptions{}, off);
  EXPECT_NE(a.message.find("references bent"), std::string::npos) << a.message;
  EXPECT_EQ(b.message.find("references bent"), std::string::npos) << b.message;
  EXPECT_LT(a.max_violation, 1e-3) << a.message;
  EXPECT_LT(a.iterations, b.iterations) << a.message << " | " << b.message;
}

// Knots and agents on several threads, reduced in knot and group order: the plan is the same bit
// for bit with one, two or three threads, under block coupling (every phase split) and exact
// coupling (the knots split, the one group's rollout not), with the rows between the samples.
TEST(BetweenSamples, ThePlanIsTheSameForAnyNumberOfThreads) {
  for (const char* coupling : {"block", "exact"}) {
    Problem p = swap_team(40, coupling == std::string("block") ? 14 : 8);
    p.guarantee = Guarantee::Continuous;
    const auto pp = planning::assemble(p, p.horizon);
    altro::Options one = altro::Options::from({});
    one.coupling = coupling;
    one.threads = 1;
    const PlanResult a = altro::solve(pp, PlanOptions{}, one);
    EXPECT_LT(a.max_violation, 1e-3) << a.message;
    for (int threads : {2, 3}) {
      altro::Options many = one;
      many.threads = threads;
      const PlanResult b = altro::solve(pp, PlanOptions{}, many);
      EXPECT_EQ(a.iterations, b.iterations) << coupling << ", " << threads << " threads";
      EXPECT_EQ(a.max_violation, b.max_violation) << coupling << ", " << threads << " threads";
      ASSERT_EQ(a.plan.u.size(), b.plan.u.size());
      for (size_t k = 0; k < a.plan.u.size(); ++k) ASSERT_EQ(a.plan.u[k], b.plan.u[k]) << coupling << ", step " << k;
    }
  }
}

// The solver keeps a period's midpoint and its Jacobians from the rollout and the linearization
// instead of integrating half a period again (solver_setup.cpp, solver_ilqr.cpp): exact only if
// the first half of the substeps gives flow_point's numbers bit for bit. Unicycle (3 states, 2
// inputs) and pendulum (2, 1) take the unrolled sweeps; both checked against a separate run.
TEST(BetweenSamples, TheRolloutsMidpointIsFlowPointsBitForBit) {
  const Problem uni = testproblems::unicycle_crossing(10), pend = testproblems::pendulum_problem(10);
  struct Case {
    const Dynamics* f;
    Eigen::VectorXd x, u;
  };
  const std::vector<Case> cases = {{uni.agents[0].dynamics.get(), Eigen::Vector3d(0.3, -1.7, 2.9), Eigen::Vector2d(0.8, -1.3)},
                                   {pend.agents[0].dynamics.get(), Eigen::Vector2d(2.1, -0.7), Eigen::VectorXd::Constant(1, 1.9)}};
  for (const auto& c : cases)
    for (const double tau : {0.1, 0.3, 0.07})
      for (const int substeps : {2, 4, 6}) {
        const int n = c.f->state_dim(), m = c.f->input_dim();
        std::vector<double> ref(n), mine(n), A(n * n), B(n * m), Am(n * n), Bm(n * m), Ar(n * n), Br(n * m);
        flow_point(*c.f, c.x.data(), c.u.data(), tau, substeps, 1, 1, ref.data(), nullptr, nullptr);
        rk4_step<double>(*c.f, c.x.data(), c.u.data(), nullptr, tau, substeps, mine.data(), substeps / 2);
        EXPECT_EQ(ref, mine) << "tau " << tau << " substeps " << substeps;
        const FlowPointStep half = flow_point_step(tau, substeps, 1, 1);
        altro::rk4_jacobians_staged(*c.f, c.x.data(), c.u.data(), half.h, half.substeps, Ar.data(), Br.data());
        altro::rk4_jacobians_staged(*c.f, c.x.data(), c.u.data(), tau, substeps, A.data(), B.data(), ~0u, Am.data(),
                                    Bm.data(), substeps / 2);
        EXPECT_EQ(Ar, Am) << "tau " << tau << " substeps " << substeps;
        EXPECT_EQ(Br, Bm);
        // The whole period's Jacobians are unchanged by keeping the midpoint's.
        std::vector<double> A0(n * n), B0(n * m);
        altro::rk4_jacobians_staged(*c.f, c.x.data(), c.u.data(), tau, substeps, A0.data(), B0.data());
        EXPECT_EQ(A0, A);
        EXPECT_EQ(B0, B);
      }
}
