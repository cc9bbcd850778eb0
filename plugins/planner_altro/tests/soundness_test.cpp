// End to end: plan the examples, then perturb every step of the plan inside the eps-boxes
// (corners and random points) and check the *real* specification on the perturbed states. This
// is what the eps-robust plan promises the tracker (paper Theorem 3.1).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "altro_solver.hpp"
#include "bench/plan_scenarios.hpp"
#include "marsyn/core/planning/geometry.hpp"
#include "marsyn/core/planning/plan.hpp"

using namespace marsyn;

namespace {

class Altro final : public Planner {
 public:
  explicit Altro(const Params& p) : o_(altro::Options::from(p)) {}
  std::string name() const override { return "altro"; }
  PlanResult solve(const PlanningProblem& p, const PlanOptions& r) const override { return altro::solve(p, r, o_); }
  altro::Options o_;
};

// The smallest margin of the real (not eps-robust) specification over perturbed states.
double sampled_real_margin(const Problem& p, const std::vector<NominalTrajectory>& plan, int samples,
                           std::string& where) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const int N = static_cast<int>(p.agents.size());
  const int T = static_cast<int>(plan[0].u.size());
  double worst = 1e300;
  auto note = [&](double v, const std::string& what, int k) {
    if (v < worst) {
      worst = v;
      where = what + " at step " + std::to_string(k);
    }
  };
  for (int k = 0; k <= T; ++k)
    for (int s = 0; s < samples; ++s) {
      std::vector<Eigen::Vector2d> q(N);
      for (int i = 0; i < N; ++i) {
        const auto& a = p.agents[i];
        Eigen::VectorXd y = plan[i].x[k];
        for (int c = 0; c < a.n(); ++c) {
          // Half the samples on the box's corners, where the extremes of monotone maps lie.
          const double r = s % 2 ? (unit(rng) > 0 ? 1.0 : -1.0) : unit(rng);
          y[c] += r * a.tube.eps[c];
        }
        for (int c = 0; c < a.n(); ++c)
          note(std::min(y[c] - a.state_bounds.lo[c], a.state_bounds.hi[c] - y[c]), "X of " + a.name, k);
        if (k == T)
          for (int c = 0; c < a.n(); ++c) note(std::min(y[c] - a.goal.lo[c], a.goal.hi[c] - y[c]), "Goal of " + a.name, k);
        workspace_point(*a.dynamics, a.workspace, y.data(), q[i].data());
        for (const auto& o : p.obstacles) {
          const double d = p.delta_norm == Norm::Inf
                               ? planning::signed_distance(planning::grow_by_box(o.vertices, p.delta, p.delta), q[i])
                               : planning::signed_distance(o.vertices, q[i]) - p.delta;
          note(d, "obstacle " + o.name + " vs " + a.name, k);
        }
      }
      if (p.pairwise_collision)
        for (int i = 0; i < N; ++i)
          for (int j = i + 1; j < N; ++j) {
            const Eigen::Vector2d d = q[i] - q[j];
            note((p.delta_norm == Norm::Inf ? d.cwiseAbs().maxCoeff() : d.norm()) - p.delta,
                 "collision " + p.agents[i].name + " vs " + p.agents[j].name, k);
          }
      for (const auto& f : p.formation)
        note(f.mu - std::abs((q[f.i] - q[f.j]).norm() - f.lambda), "formation", k);
    }
  return worst;
}

}  // namespace

class Soundness : public ::testing::TestWithParam<const char*> {};

TEST_P(Soundness, PerturbationsWithinEpsSatisfyTheRealSpec) {
  auto sc = bench::make_scenario(GetParam());
  const Altro planner(sc.planner_params);
  const auto out = planning::plan(sc.problem, planner, {});
  ASSERT_TRUE(out.feasible) << planning::summary(sc.problem, out);
  std::string where;
  const double m = sampled_real_margin(sc.problem, out.nominal, 200, where);
  EXPECT_GE(m, 0.0) << where;
  // The real spec must be met with at least the eps-robust margin (perturbations only shrink it
  // down to that bound, never below).
  EXPECT_GE(m + 1e-12, out.check.min_margin) << where;
}

INSTANTIATE_TEST_SUITE_P(Examples, Soundness,
                         ::testing::Values("multi-drone-10", "crane-vehicle", "lane-merging-6", "formation-5",
                                           "pendulum-swing-up"));

TEST(SoundnessFootprint, CraneTipMarginHoldsWhenTheCollisionConstraintBinds) {
  // The vehicle's point at the tip's height and its goal pulled towards the crane's, so the plan
  // ends pressed against the tip's margin (nonlinear footprint, interval-derived margin).
  auto sc = bench::make_scenario("crane-vehicle");
  auto& v = sc.problem.agents[1];
  v.workspace.offset[1] = 0.1;
  v.goal = {Eigen::Vector2d(4.9, -0.4), Eigen::Vector2d(5.4, 0.4)};
  const Altro planner(sc.planner_params);
  const auto out = planning::plan(sc.problem, planner, {});
  ASSERT_TRUE(out.feasible) << planning::summary(sc.problem, out);
  // Final horizontal gap between tip and vehicle: within 0.05 of delta + both margins (0.035 +
  // 0.2225 + 0.08 at the hanging tip), so the tip's margin is what keeps them apart.
  const auto& xc = out.nominal[0].x.back();
  const auto& xv = out.nominal[1].x.back();
  const double gap = std::abs(xc[0] + 0.5 * std::sin(xc[2]) - xv[0]);
  EXPECT_LT(gap, 0.035 + 0.2225 + 0.08 + 0.05) << "the collision constraint should bind";
  std::string where;
  const double m = sampled_real_margin(sc.problem, out.nominal, 400, where);
  EXPECT_GE(m, 0.0) << where;
}
