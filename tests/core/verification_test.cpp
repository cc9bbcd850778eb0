// The verification machinery must see violations where they happen and none where they do not:
// a double integrator stops 0.5 m before an obstacle. Open loop, a constant push drives it in;
// a linear feedback around the nominal keeps it out.
#include <gtest/gtest.h>

#include "marsyn/core/plugins/plugin_registry.hpp"
#include "marsyn/core/verification/verification.hpp"
#include "marsyn/sampled_map.hpp"

namespace {

using Eigen::VectorXd;

// u = u_nom(k) + K (x_nom(k) - x): enough to hold a double integrator near its nominal.
class LinearFeedback : public marsyn::Controller {
 public:
  explicit LinearFeedback(marsyn::NominalTrajectory nom) : nom_(std::move(nom)) {}
  int state_dim() const override { return 2; }
  int input_dim() const override { return 1; }
  int horizon() const override { return static_cast<int>(nom_.u.size()); }
  marsyn::ControlStatus input(const double* x, int k, double* u) const override {
    if (k >= horizon()) return marsyn::ControlStatus::OutsideHorizon;
    u[0] = nom_.u[k][0] + 4.0 * (nom_.x[k][0] - x[0]) + 4.0 * (nom_.x[k][1] - x[1]);
    return marsyn::ControlStatus::Ok;
  }
  void write(const std::string&) const override {}
  // A test controller with no continuous-time certificate.
  const std::vector<marsyn::PeriodEnclosure>& period_enclosures() const override { return none_; }

 private:
  marsyn::NominalTrajectory nom_;
  std::vector<marsyn::PeriodEnclosure> none_;
};

struct Fixture {
  marsyn::PluginRegistry registry;
  marsyn::Problem pb;
  std::vector<marsyn::NominalTrajectory> nominal;

  Fixture() {
    marsyn::AgentSpec a;
    a.name = "car";
    a.dynamics_type = "double_integrator";
    a.dynamics = registry.create<marsyn::Dynamics>("double_integrator");
    a.x0 = VectorXd::Zero(2);
    a.goal = {VectorXd::Constant(2, -10), VectorXd::Constant(2, 10)};
    a.state_bounds = a.goal;
    a.input_bounds = {VectorXd::Constant(1, -5), VectorXd::Constant(1, 5)};
    a.tube.w = (VectorXd(2) << 0.0, 0.5).finished();
    a.tube.eps = VectorXd::Constant(2, 0.3);
    a.fields.set("eta_x", VectorXd::Constant(2, 0.05));
    a.fields.set("eta_u", VectorXd::Constant(1, 0.1));
    a.workspace.index = {0, -1};
    a.workspace.offset = {0.0, 0.0};
    pb.agents.push_back(a);
    marsyn::Obstacle o;
    o.name = "wall";
    o.vertices = {{4.7, -1}, {6, -1}, {6, 1}, {4.7, 1}};
    pb.obstacles.push_back(o);
    pb.delta = 0.2;
    pb.tau = 0.1;
    // Nominal: accelerate for 1 s, brake for 1 s, then rest at p = 4 (0.5 m short of delta).
    marsyn::NominalTrajectory t;
    t.agent = "car";
    VectorXd x = a.x0;
    t.x.push_back(x);
    for (int k = 0; k < 40; ++k) {
      VectorXd u(1);
      u[0] = k < 10 ? 4.0 : k < 20 ? -4.0 : 0.0;
      VectorXd next(2);
      marsyn::rk4_step<double>(*a.dynamics, x.data(), u.data(), nullptr, 0.1, 10, next.data());
      x = next;
      t.u.push_back(u);
      t.x.push_back(x);
    }
    nominal.push_back(t);
  }
};

}  // namespace

TEST(Verification, OpenLoopDriftsIntoTheWallFeedbackDoesNot) {
  Fixture f;
  ASSERT_NEAR(f.nominal[0].x.back()[0], 4.0, 1e-9);
  std::vector<std::shared_ptr<const marsyn::Controller>> ctrls{std::make_shared<LinearFeedback>(f.nominal[0])};
  marsyn::VerificationOptions opt;
  opt.runs = 60;
  const auto rep = marsyn::verify(f.pb, f.nominal, ctrls, opt);
  EXPECT_EQ(rep.runs, 60);
  EXPECT_EQ(rep.violations, 0) << rep.worst;
  EXPECT_GT(rep.min_margin, 0.0);
  // Under +W for 4 s, open loop drifts by 0.5 * 0.5 * 16 = 4 m: into the wall.
  EXPECT_GE(rep.open_loop_violations, 1);
  EXPECT_NE(rep.open_loop_worst.find("obstacle wall vs car"), std::string::npos) << rep.open_loop_worst;
  // Per run: the parts the problem has, with the step of their smallest margin.
  ASSERT_EQ(rep.open_loop.size(), 4u);
  int into_wall = 0;
  for (const auto& r : rep.open_loop) {
    EXPECT_GE(r.obstacle.step, 0) << r.label;
    EXPECT_EQ(r.collision.step, -1) << "one agent: no pairs";
    EXPECT_EQ(r.formation.step, -1);
    EXPECT_LT(r.goal, 1e299);
    if (r.obstacle.margin < 0) {
      ++into_wall;
      EXPECT_FALSE(r.satisfied);
    }
  }
  EXPECT_GE(into_wall, 1);
}

TEST(Verification, ABrokenControllerIsCaught) {
  Fixture f;
  // Zero feedback gain in the wrong direction: pushes away from the nominal.
  class Bad : public LinearFeedback {
   public:
    using LinearFeedback::LinearFeedback;
    marsyn::ControlStatus input(const double* x, int k, double* u) const override {
      LinearFeedback::input(x, k, u);
      u[0] = 5.0;
      return marsyn::ControlStatus::Ok;
    }
  };
  std::vector<std::shared_ptr<const marsyn::Controller>> ctrls{std::make_shared<Bad>(f.nominal[0])};
  marsyn::VerificationOptions opt;
  opt.runs = 10;
  const auto rep = marsyn::verify(f.pb, f.nominal, ctrls, opt);
  EXPECT_EQ(rep.violations, 10);
  EXPECT_EQ(rep.tube_violations, 10);
}

TEST(Verification, ScenariosCoverEveryModeDeterministically) {
  const auto a = marsyn::verification_scenarios(100, 7), b = marsyn::verification_scenarios(100, 7);
  ASSERT_EQ(a.size(), 100u);
  int counts[6] = {0, 0, 0, 0, 0, 0};  // one per DisturbanceMode, Adversarial included
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].seed, b[i].seed);
    ++counts[static_cast<int>(a[i].mode)];
  }
  for (int c : counts) EXPECT_GT(c, 0);
}

// No --runs: 1000 runs for teams of up to 100 agents, then 100,000 agent runs over the team, at
// least 200; a run count asked for is kept (the small fixture: 10 runs above, 0 means the default).
TEST(Verification, TheDefaultRunsSpreadAHundredThousandAgentRunsOverLargeTeams) {
  EXPECT_EQ(marsyn::default_verification_runs(1), 1000);
  EXPECT_EQ(marsyn::default_verification_runs(100), 1000);
  EXPECT_EQ(marsyn::default_verification_runs(101), 990);
  EXPECT_EQ(marsyn::default_verification_runs(400), 250);
  EXPECT_EQ(marsyn::default_verification_runs(1000), 200);
  EXPECT_EQ(marsyn::default_verification_runs(5000), 200);
  EXPECT_EQ(marsyn::VerificationOptions{}.runs, 0);
}
