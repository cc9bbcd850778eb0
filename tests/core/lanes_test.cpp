// Lanes::kWidth runs in lockstep (lanes.hpp, closed_loop.hpp): a lane computes what double computes
// (arithmetic bit for bit, elementary functions within libmvec's documented 4 ulp), and a run
// simulated in a batch is, to the last bit, the run simulated alone, whatever the other lanes
// hold: the verification's results must not depend on how runs were grouped (threads, ranks).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "marsyn/core/plugins/plugin_registry.hpp"
#include "marsyn/core/verification/closed_loop.hpp"
#include "marsyn/core/verification/lanes_rk4.hpp"
#include "marsyn/core/verification/spec_monitor.hpp"
#include "marsyn/lanes.hpp"
#include "marsyn/sampled_map.hpp"

namespace {

using Eigen::Vector2d;
using Eigen::VectorXd;

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Distance in units in the last place between two finite doubles of the same sign.
double ulps(double a, double b) {
  if (a == b) return 0;
  return std::abs(a - b) / std::abs(std::nextafter(a, b) - a);
}

TEST(Lanes, ArithmeticIsTheScalarsBitForBit) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> d(-50, 50);
  for (int t = 0; t < 2000; ++t) {
    marsyn::Lanes a, b;
    for (int l = 0; l < marsyn::Lanes::kWidth; ++l) a[l] = d(rng), b[l] = d(rng);
    const marsyn::Lanes s = a + b, m = a - b, p = a * b, q = a / b, c = 0.5 * a + b / 3.0, r = marsyn::sqrt(marsyn::abs(a));
    for (int l = 0; l < marsyn::Lanes::kWidth; ++l) {
      ASSERT_TRUE(same_bits(s[l], a[l] + b[l]));
      ASSERT_TRUE(same_bits(m[l], a[l] - b[l]));
      ASSERT_TRUE(same_bits(p[l], a[l] * b[l]));
      ASSERT_TRUE(same_bits(q[l], a[l] / b[l]));
      ASSERT_TRUE(same_bits(c[l], 0.5 * a[l] + b[l] / 3.0));
      ASSERT_TRUE(same_bits(r[l], std::sqrt(std::abs(a[l]))));
    }
  }
}

TEST(Lanes, ElementaryFunctionsWithinFourUlpOfLibm) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> wide(-20, 20), positive(1e-3, 50), small(-1.4, 1.4);
  double worst = 0;
  for (int t = 0; t < 5000; ++t) {
    marsyn::Lanes a, p, s;
    for (int l = 0; l < marsyn::Lanes::kWidth; ++l) a[l] = wide(rng), p[l] = positive(rng), s[l] = small(rng);
    const marsyn::Lanes fs = marsyn::sin(a), fc = marsyn::cos(a), ft = marsyn::tan(s), fe = marsyn::exp(s),
                        fl = marsyn::log(p), fa = marsyn::atan(a), as = marsyn::asin(0.7 * s), ac = marsyn::acos(0.7 * s),
                        sh = marsyn::sinh(s), ch = marsyn::cosh(s), th = marsyn::tanh(a);
    for (int l = 0; l < marsyn::Lanes::kWidth; ++l) {
      worst = std::max({worst, ulps(fs[l], std::sin(a[l])), ulps(fc[l], std::cos(a[l])), ulps(ft[l], std::tan(s[l])),
                        ulps(fe[l], std::exp(s[l])), ulps(fl[l], std::log(p[l])), ulps(fa[l], std::atan(a[l])),
                        ulps(as[l], std::asin(0.7 * s[l])), ulps(ac[l], std::acos(0.7 * s[l])),
                        ulps(sh[l], std::sinh(s[l])), ulps(ch[l], std::cosh(s[l])), ulps(th[l], std::tanh(a[l]))});
    }
  }
  EXPECT_LE(worst, 4.0) << (marsyn::lanes_vector_math() ? "libmvec" : "libm lane by lane");
  if (!marsyn::lanes_vector_math()) EXPECT_EQ(worst, 0.0);
}

TEST(Lanes, SineAndCosineWithinFourUlpWhereTheReductionIsHardest) {
  // Next to multiples of pi/2 (the result is the small remainder, all of whose bits the argument
  // reduction must get), tiny and large angles, and not finite.
  std::vector<double> xs;
  for (int k = -40000; k <= 40000; k += 7)
    for (double d : {-3e-16, 0.0, 2e-16}) xs.push_back(k * 1.5707963267948966 * (1 + d));
  for (int e = -300; e < 17; ++e) xs.push_back(std::ldexp(1.0, e)), xs.push_back(-std::ldexp(1.3, e));
  for (double x : {1e5, 1e5 + 1, -2e5, 6.3e8, 1e300, 0.0, -0.0, 0.7853981633974483, 2.356194490192345}) xs.push_back(x);
  while (xs.size() % marsyn::Lanes::kWidth != 0) xs.push_back(1.0);
  double worst = 0;
  for (std::size_t i = 0; i < xs.size(); i += marsyn::Lanes::kWidth) {
    marsyn::Lanes a, s, c;
    for (int l = 0; l < marsyn::Lanes::kWidth; ++l) a[l] = xs[i + static_cast<size_t>(l)];
    marsyn::sincos(a, s, c);
    const marsyn::Lanes s1 = marsyn::sin(a), c1 = marsyn::cos(a);
    for (int l = 0; l < marsyn::Lanes::kWidth; ++l) {
      SCOPED_TRACE(a[l]);
      // sin() and cos() are sincos()'s halves, bit for bit.
      ASSERT_TRUE(same_bits(s[l], s1[l]) && same_bits(c[l], c1[l]));
      ASSERT_TRUE(std::signbit(s[l]) == std::signbit(std::sin(a[l])) || std::sin(a[l]) == 0);
      worst = std::max({worst, ulps(s[l], std::sin(a[l])), ulps(c[l], std::cos(a[l]))});
    }
  }
  EXPECT_LE(worst, 4.0);
  marsyn::Lanes a(std::nan("")), s, c;
  a[1] = INFINITY;
  marsyn::sincos(a, s, c);
  for (int l = 0; l < marsyn::Lanes::kWidth; ++l) EXPECT_TRUE(std::isnan(s[l]) && std::isnan(c[l]));
}

// The lane-by-lane loop a hand-written Dynamics inherits, against a model's own Lanes field.
class HandWritten : public marsyn::Dynamics {
 public:
  explicit HandWritten(const marsyn::Dynamics& f) : f_(f) {}
  std::string type() const override { return "hand"; }
  int state_dim() const override { return f_.state_dim(); }
  int input_dim() const override { return f_.input_dim(); }
  std::vector<std::string> state_names() const override { return f_.state_names(); }
  std::vector<std::string> input_names() const override { return f_.input_names(); }
  void field(const double* x, const double* u, double* dx) const override { f_.field(x, u, dx); }
  void field(const marsyn::DualD* x, const marsyn::DualD* u, marsyn::DualD* dx) const override { f_.field(x, u, dx); }
  void field(const marsyn::Interval* x, const marsyn::Interval* u, marsyn::Interval* dx) const override { f_.field(x, u, dx); }
  void field(const marsyn::DualI* x, const marsyn::DualI* u, marsyn::DualI* dx) const override { f_.field(x, u, dx); }
  using marsyn::Dynamics::field;

 private:
  const marsyn::Dynamics& f_;
};

TEST(Lanes, HandWrittenDynamicsGetsTheScalarFieldPerLane) {
  marsyn::PluginRegistry registry;
  const auto model = registry.create<marsyn::Dynamics>("double_integrator");
  const HandWritten hand(*model);
  const int n = model->state_dim(), m = model->input_dim();
  std::vector<marsyn::Lanes> x(n), u(m), a(n), b(n);
  for (int l = 0; l < marsyn::Lanes::kWidth; ++l) {
    for (int i = 0; i < n; ++i) x[i][l] = 0.3 * l - 0.7 * i;
    for (int j = 0; j < m; ++j) u[j][l] = 1.1 * l + j;
  }
  model->field(x.data(), u.data(), a.data());
  hand.field(x.data(), u.data(), b.data());
  for (int i = 0; i < n; ++i)
    for (int l = 0; l < marsyn::Lanes::kWidth; ++l) {
      std::vector<double> xs(n), us(m), d(n);
      for (int c = 0; c < n; ++c) xs[c] = x[c][l];
      for (int c = 0; c < m; ++c) us[c] = u[c][l];
      model->field(xs.data(), us.data(), d.data());
      EXPECT_TRUE(same_bits(a[i][l], d[i]));
      EXPECT_TRUE(same_bits(b[i][l], d[i]));
    }
}

// A controller that pulls toward the nominal (per agent, local state and time only).
class Pull : public marsyn::Controller {
 public:
  explicit Pull(marsyn::NominalTrajectory t) : t_(std::move(t)) {}
  marsyn::ControlStatus input(const double* x, int k, double* u) const override {
    u[0] = t_.u[k][0] + 0.5 * (t_.x[k][2] - x[2]);
    u[1] = t_.u[k][1] - 0.8 * (t_.x[k][2] - x[2]);
    return k == 11 && x[0] > 100 ? marsyn::ControlStatus::OutsideDomain : marsyn::ControlStatus::Ok;
  }
  int state_dim() const override { return 3; }
  int input_dim() const override { return 2; }
  int horizon() const override { return static_cast<int>(t_.u.size()); }
  void write(const std::string&) const override {}
  const std::vector<marsyn::PeriodEnclosure>& period_enclosures() const override { return none_; }

 private:
  marsyn::NominalTrajectory t_;
  std::vector<marsyn::PeriodEnclosure> none_;
};

TEST(ClosedLoopBatch, ARunInABatchIsTheRunAlone) {
  marsyn::PluginRegistry registry;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> start(-5, 5), in(-1.2, 1.2);
  marsyn::Problem pb;
  for (int i = 0; i < 7; ++i) {
    marsyn::AgentSpec a;
    a.name = "a" + std::to_string(i);
    a.dynamics_type = "unicycle";
    a.dynamics = registry.create<marsyn::Dynamics>("unicycle");
    a.x0 = VectorXd(3);
    a.x0 << start(rng), start(rng), start(rng);
    a.goal = {VectorXd::Constant(3, -100), VectorXd::Constant(3, 100)};
    a.state_bounds = a.goal;
    a.input_bounds = {VectorXd::Constant(2, -2), VectorXd::Constant(2, 2)};
    a.tube.w = (VectorXd(3) << 0.05, 0.1, 0.2).finished();
    a.tube.eps = VectorXd::Constant(3, 1.0);
    a.workspace.index = {0, 1};
    a.workspace.offset = {0.0, 0.0};
    pb.agents.push_back(a);
  }
  marsyn::Obstacle ob;
  ob.name = "block";
  ob.vertices = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  pb.obstacles.push_back(ob);
  pb.delta = 0.2;
  pb.tau = 0.1;
  std::vector<marsyn::NominalTrajectory> nominal;
  std::vector<std::shared_ptr<const marsyn::Controller>> controllers;
  for (const auto& a : pb.agents) {
    marsyn::NominalTrajectory t;
    t.agent = a.name;
    VectorXd x = a.x0;
    t.x.push_back(x);
    for (int k = 0; k < 20; ++k) {
      const VectorXd u = (VectorXd(2) << in(rng), in(rng)).finished();
      VectorXd next(3);
      marsyn::rk4_step<double>(*a.dynamics, x.data(), u.data(), nullptr, pb.tau, 20, next.data());
      t.u.push_back(u);
      t.x.push_back(x = next);
    }
    nominal.push_back(t);
    controllers.push_back(std::make_shared<Pull>(t));
  }
  const marsyn::SpecMonitor monitor(pb);
  const std::vector<marsyn::Scenario> scenarios = {{marsyn::DisturbanceMode::Adversarial, 1, 0},
                                                   {marsyn::DisturbanceMode::UniformRandom, 2, 0},
                                                   {marsyn::DisturbanceMode::VertexSwitching, 3, 0},
                                                   {marsyn::DisturbanceMode::PaperConstant, 4, 1},
                                                   {marsyn::DisturbanceMode::ConstantVertex, 5, 0},
                                                   {marsyn::DisturbanceMode::Adversarial, 6, 0},
                                                   {marsyn::DisturbanceMode::None, 7, 0},
                                                   {marsyn::DisturbanceMode::PaperConstant, 8, 2}};
  static_assert(marsyn::Lanes::kWidth <= 8);
  for (bool closed : {false, true}) {
    marsyn::SimulationSetup setup{&pb, nominal, {}, 20, &monitor};
    if (closed) setup.controllers = controllers;
    setup.keep_dense = true;
    // Full batches, batches of three and four (the other lanes padded), in other orders.
    std::vector<std::vector<int>> groups = {{0, 1, 2, 3}, {2, 0, 3}, {3, 2, 1, 0}, {7, 5, 6, 4}};
    groups.push_back({});
    for (int r = 0; r < marsyn::Lanes::kWidth; ++r) groups.back().push_back(r);
    groups.push_back(std::vector<int>(groups.back().rbegin(), groups.back().rend()));
    for (const auto& g : groups) {
      std::vector<marsyn::Scenario> batch;
      for (int r : g) batch.push_back(scenarios[r]);
      const std::vector<marsyn::ClosedLoopRun> together = marsyn::simulate(setup, batch);
      ASSERT_EQ(together.size(), g.size());
      for (std::size_t b = 0; b < g.size(); ++b) {
        SCOPED_TRACE(std::string(closed ? "closed" : "open") + " loop, " + marsyn::to_string(batch[b].mode));
        const marsyn::ClosedLoopRun alone = marsyn::simulate(setup, batch[b]);
        const marsyn::ClosedLoopRun& t = together[b];
        ASSERT_EQ(t.states.size(), alone.states.size());
        for (std::size_t k = 0; k < t.states.size(); ++k) ASSERT_TRUE(t.states[k] == alone.states[k]) << "step " << k;
        ASSERT_EQ(t.dense_states.size(), alone.dense_states.size());
        for (std::size_t k = 0; k < t.dense_states.size(); ++k) ASSERT_TRUE(t.dense_states[k] == alone.dense_states[k]);
        EXPECT_TRUE(same_bits(t.between.min(), alone.between.min()));
        EXPECT_EQ(t.between_worst, alone.between_worst);
        EXPECT_TRUE(same_bits(t.sampled.min_margin, alone.sampled.min_margin));
        EXPECT_EQ(t.sampled.worst, alone.sampled.worst);
        EXPECT_TRUE(same_bits(t.max_tube_excess, alone.max_tube_excess));
        EXPECT_EQ(t.outside_domain_agent, alone.outside_domain_agent);
      }
    }
  }
  // The runs differ from each other (a batch that copied one lane into all would pass the above
  // only if the runs were equal).
  marsyn::SimulationSetup setup{&pb, nominal, controllers, 20, &monitor};
  const auto all = marsyn::simulate(setup, std::span(scenarios).first(marsyn::Lanes::kWidth));
  for (std::size_t a = 0; a < all.size(); ++a)
    for (std::size_t b = a + 1; b < all.size(); ++b) EXPECT_FALSE(all[a].states.back() == all[b].states.back());
}

// The runs' own integrator (lanes_rk4.hpp) against rk4_step_lanes, the reference it replaces: the
// same states bit for bit over 40 chained substeps, on every dynamics plugin (the unicycle and the
// double integrator take stage 3's field from stage 2, the others cannot), with per-lane states,
// inputs and disturbances. Fails when the field is reused where a column it reads differs (a
// heading or velocity not held, as for the pendulum), or when the stage arithmetic is reordered.
// The input changes every tenth substep (a new sample): stage 1's field taken from the last
// stage 4 under the old input fails here too.
TEST(LanesRk4, EveryModelStepsAsRk4StepLanesBitForBit) {
  marsyn::PluginRegistry registry;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> d(-1.5, 1.5);
  int reusing = 0, reusing_last = 0;
  for (const char* name : {"unicycle", "bicycle", "cartpole", "double_integrator", "pendulum", "planar_quadrotor", "quadrotor"}) {
    SCOPED_TRACE(name);
    const auto f = registry.create<marsyn::Dynamics>(name);
    const int n = f->state_dim(), m = f->input_dim();
    marsyn::verification_detail::LanesRk4 rk(*f);
    std::vector<marsyn::Lanes> x(n), u(m), w(n), a(n), b(n);
    for (int l = 0; l < marsyn::Lanes::kWidth; ++l) {
      for (auto& v : x) v[l] = d(rng);
      for (auto& v : u) v[l] = d(rng);
    }
    std::vector<marsyn::Lanes> mine = x, ref = x;
    for (int s = 0; s < 40; ++s) {
      // A new disturbance every fifth substep, as the adversary re-chooses it.
      if (s % 5 == 0)
        for (auto& v : w)
          for (int l = 0; l < marsyn::Lanes::kWidth; ++l) v[l] = 0.1 * d(rng);
      if (s % 10 == 0 && s > 0)
        for (auto& v : u)
          for (int l = 0; l < marsyn::Lanes::kWidth; ++l) v[l] = d(rng);
      rk.step(mine.data(), u.data(), w.data(), 0.1, 20, a.data());
      marsyn::rk4_step_lanes(*f, ref.data(), u.data(), w.data(), 0.1, 20, b.data(), 1);
      mine = a;
      ref = b;
      for (int i = 0; i < n; ++i)
        for (int l = 0; l < marsyn::Lanes::kWidth; ++l)
          ASSERT_TRUE(same_bits(mine[i][l], ref[i][l])) << "substep " << s << ", state " << i << ", lane " << l;
    }
    reusing += rk.reuses_stage_two() ? 1 : 0;
    reusing_last += rk.reuses_stage_four() ? 1 : 0;
  }
  EXPECT_GE(reusing, 2);  // the unicycle and the double integrator at least: the saving is exercised
  EXPECT_GE(reusing_last, 2);
}

}  // namespace
