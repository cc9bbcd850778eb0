// Per dynamics model: >= 1e6 sampled successors all inside the computed boxes (and inside the
// reused, shifted covers the synthesis actually uses), and a 10%-shrunken box must leak.
#include <gtest/gtest.h>

#include <random>

#include "abcd_tracker.hpp"
#include "controller_file.hpp"
#include "sampler.hpp"
#include "track_scenarios.hpp"

using namespace marsyn;
using Steps = std::vector<long long>;  // a figure counted per step (TrackerStats::figures)
using namespace marsyn::abcd;
using marsyn::abcd::testing::SamplerSetup;
using marsyn::abcd::testing::sample_successors;

namespace {

SamplerSetup unicycle_setup(const Dynamics& f) {
  SamplerSetup s;
  s.f = &f;
  s.origin = {-1, -1, -2};
  s.eta_x = {0.025, 0.025, 0.03};
  s.w = {0.0, 0.025, 0.025};
  s.u_lo = {-2.4, -2.4};
  s.u_hi = {2.4, 2.4};
  s.eta_u = {0.3, 0.3};
  s.region_lo = {0, 0, -3.2};
  s.region_hi = {10, 10, 3.2};
  return s;
}
SamplerSetup cartpole_setup(const Dynamics& f) {
  SamplerSetup s;
  s.f = &f;
  s.origin = {-0.195, -1.99, 1.20, -5.44};
  s.eta_x = {0.015, 0.035, 0.016, 0.064};
  s.w = {0, 0.05, 0, 0};
  s.u_lo = {-7};
  s.u_hi = {7};
  s.eta_u = {0.2};
  s.region_lo = {0, -1.5, 1.8, -3};
  s.region_hi = {5, 3, 4.4, 3};
  return s;
}
SamplerSetup double_integrator_setup(const Dynamics& f) {
  SamplerSetup s;
  s.f = &f;
  s.origin = {3, -3};
  s.eta_x = {0.01, 0.015};
  s.w = {0, 0.1};
  s.u_lo = {-3};
  s.u_hi = {3};
  s.eta_u = {0.1};
  s.region_lo = {3.5, -2.5};
  s.region_hi = {8.5, 1.5};
  return s;
}
SamplerSetup pendulum_setup(const Dynamics& f) {
  SamplerSetup s;
  s.f = &f;
  s.origin = {-4, -4};
  s.eta_x = {0.01, 0.01};
  s.w = {0, 0.01};
  s.u_lo = {-4};
  s.u_hi = {4};
  s.eta_u = {0.25};
  s.region_lo = {-0.5, -3};
  s.region_hi = {3.8, 3};
  return s;
}

void expect_sound(SamplerSetup s) {
  const auto r = sample_successors(s);
  EXPECT_GE(r.samples, 1000000);
  EXPECT_EQ(r.escapes, 0) << "worst escape " << r.worst << " cells";
  EXPECT_EQ(r.cover_escapes, 0);
  EXPECT_LT(r.unbounded, s.boxes / 10);
}

void expect_shrunk_box_leaks(SamplerSetup s) {
  s.shrink = 0.1;
  s.boxes = 100;
  s.samples_per_box = 1000;
  const auto r = sample_successors(s);
  EXPECT_GT(r.escapes, 0) << "a box 10% smaller than computed held every sample: the sampler is too weak";
}

}  // namespace

TEST(SuccessorSoundness, Unicycle) {
  models::Unicycle f;
  expect_sound(unicycle_setup(f));
}
TEST(SuccessorSoundness, UnicycleShrunkLeaks) {
  models::Unicycle f;
  expect_shrunk_box_leaks(unicycle_setup(f));
}
TEST(SuccessorSoundness, CartPole) {
  models::CartPole f;
  auto s = cartpole_setup(f);
  s.samples_per_box = 2500;
  expect_sound(s);
}
TEST(SuccessorSoundness, CartPoleShrunkLeaks) {
  models::CartPole f;
  expect_shrunk_box_leaks(cartpole_setup(f));
}
TEST(SuccessorSoundness, DoubleIntegrator) {
  models::DoubleIntegrator f;
  expect_sound(double_integrator_setup(f));
}
TEST(SuccessorSoundness, DoubleIntegratorShrunkLeaks) {
  models::DoubleIntegrator f;
  expect_shrunk_box_leaks(double_integrator_setup(f));
}
TEST(SuccessorSoundness, Pendulum) {
  models::Pendulum f;
  expect_sound(pendulum_setup(f));
}
TEST(SuccessorSoundness, PendulumShrunkLeaks) {
  models::Pendulum f;
  expect_shrunk_box_leaks(pendulum_setup(f));
}

// More substeps and a single substep are sound too (the option changes tightness only).
TEST(SuccessorSoundness, UnicycleOneAndFourSubsteps) {
  models::Unicycle f;
  for (int sub : {1, 4}) {
    auto s = unicycle_setup(f);
    s.successor.substeps = sub;
    s.boxes = 60;
    s.samples_per_box = 2000;
    const auto r = sample_successors(s);
    EXPECT_EQ(r.escapes, 0) << sub << " substeps";
  }
}

// A model hook is intersected with the generic box: an exact hook for the double integrator
// (closed form) must stay sound and be at least as tight.
namespace {
class ExactDoubleIntegrator : public SuccessorHook {
 public:
  bool successor(const Interval* cell, const double* u, const double* w, double tau, double* lo,
                 double* hi) const override {
    const Interval t(tau), U(u[0]), Wv(-w[1], w[1]), Wp(-w[0], w[0]);
    // p(t) = p + v t + (u + w_v) t^2 / 2 + w_p t (each at its extreme, constant disturbance
    // maximizes the reach of a double integrator), v(t) = v + (u + w_v) t.
    const Interval p = cell[0] + cell[1] * t + (U + Wv) * t * t / Interval(2.0) + Wp * t;
    const Interval v = cell[1] + (U + Wv) * t;
    lo[0] = p.lower();
    hi[0] = p.upper();
    lo[1] = v.lower();
    hi[1] = v.upper();
    return true;
  }
};
}  // namespace

// A model that carries its own bound: the tracker finds the hook through the Dynamics object.
namespace {
class DoubleIntegratorWithHook : public models::DoubleIntegrator, public ExactDoubleIntegrator {};
}  // namespace

TEST(SuccessorSoundness, TrackerUsesAModelsHookAndStaysCorrect) {
  auto p = scenarios::vehicle();
  const auto plain = AbcdTracker().track(p, TrackOptions{});
  p.dynamics = std::make_shared<DoubleIntegratorWithHook>();
  const auto hooked = AbcdTracker().track(p, TrackOptions{});
  ASSERT_EQ(plain.status, TrackerStatus::ControllerFound);
  ASSERT_EQ(hooked.status, TrackerStatus::ControllerFound);
  // An exact bound can only grow the winning set.
  EXPECT_GE(hooked.stats.get<Steps>("winning_cells_per_step")[0], plain.stats.get<Steps>("winning_cells_per_step")[0]);
  const auto& c = *hooked.controller;
  std::mt19937_64 rng(4);
  for (int run = 0; run < 20; ++run) {
    Eigen::VectorXd x0 = p.nominal.x[0];
    if (!dynamic_cast<const GridController&>(c).winning(x0.data(), 0)) continue;
    ClosedLoopOptions o;
    o.mode = run % 2 ? TubeDisturbance::VertexSwitching : TubeDisturbance::UniformRandom;
    o.seed = rng();
    EXPECT_TRUE(simulate_closed_loop(*p.dynamics, c, x0, p.nominal.x, p.tube.eps, p.tube.w, o).in_tube());
  }
}

TEST(SuccessorSoundness, ModelHookIsSampledTheSameWay) {
  models::DoubleIntegrator f;
  ExactDoubleIntegrator hook;
  auto s = double_integrator_setup(f);
  s.hook = &hook;
  expect_sound(s);
  expect_shrunk_box_leaks(s);
}
