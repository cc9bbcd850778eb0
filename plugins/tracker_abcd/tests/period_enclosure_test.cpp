// The continuous-time half of the guarantee: every state the system takes between two samples
// lies in the enclosure of its part of the period. Per dynamics model >= 1e6 sampled
// intermediate states (disturbances uniform per fine substep, a constant vertex, or a vertex
// switching inside the period), and a 10%-shrunken enclosure must leak. Then the same for the
// enclosures a synthesized controller stores, in closed loop.
#include <gtest/gtest.h>

#include <random>

#include "abcd_tracker.hpp"
#include "tube_simulation.hpp"
#include "controller_file.hpp"
#include "input_grid.hpp"
#include "track_scenarios.hpp"
#include "successor_box.hpp"
#include "uniform_grid.hpp"

using namespace marsyn;
using namespace marsyn::abcd;

namespace {

struct EnclosureSetup {
  const Dynamics* f = nullptr;
  std::vector<double> origin, eta_x, w, u_lo, u_hi, eta_u, region_lo, region_hi;
  double tau = 0.1;
  int parts = 4;         // enclosure substeps
  int fine = 10;         // RK4 steps per part in the sampler
  int cells = 250;
  int samples_per_cell = 400;
  double shrink = 0.0;  // fraction of each box's radius cut on every side
  int tracker_substeps = 2;
};

struct Result {
  long long samples = 0, escapes = 0, unbounded = 0;
};

// The state at every fine step t_q = q tau / (parts * fine) must lie in the box of each part
// whose closed time interval contains t_q.
Result sample(const EnclosureSetup& s) {
  const Dynamics& f = *s.f;
  const int n = f.state_dim(), m = f.input_dim(), P = s.parts, Q = s.parts * s.fine;
  const UniformGrid g(s.origin, s.eta_x);
  const InputGrid ug(s.u_lo, s.u_hi, s.eta_u);
  SuccessorOptions so;
  so.tau = s.tau;
  so.substeps = s.tracker_substeps;
  const SuccessorBox sb(f, s.w, so);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Result r;
  std::vector<Interval> boxes(static_cast<size_t>(P * n));
  for (int c = 0; c < s.cells; ++c) {
    Interval cell[kMaxDim];
    double clo[kMaxDim], chi[kMaxDim];
    for (int i = 0; i < n; ++i) {
      const std::int64_t idx = g.index(i, s.region_lo[i] + unit(rng) * (s.region_hi[i] - s.region_lo[i]));
      cell[i] = g.cell(i, idx);
      clo[i] = g.origin()[i] + static_cast<double>(idx) * g.eta()[i];
      chi[i] = clo[i] + g.eta()[i];
    }
    const std::int64_t j = static_cast<std::int64_t>(unit(rng) * static_cast<double>(ug.size())) % ug.size();
    std::vector<double> u(static_cast<size_t>(m));
    ug.value(j, u.data());
    if (!sb.enclose(cell, u.data(), P, boxes.data())) {
      ++r.unbounded;
      continue;
    }
    std::vector<double> lo(boxes.size()), hi(boxes.size());
    for (size_t k = 0; k < boxes.size(); ++k) {
      const double rad = 0.5 * (boxes[k].upper() - boxes[k].lower());
      lo[k] = boxes[k].lower() + s.shrink * rad;
      hi[k] = boxes[k].upper() - s.shrink * rad;
    }
    for (int q = 0; q < s.samples_per_cell; ++q) {
      Eigen::VectorXd x(n);
      const bool corner = q % 8 == 0;
      for (int i = 0; i < n; ++i) x[i] = corner ? ((rng() & 1u) ? clo[i] : chi[i]) : clo[i] + unit(rng) * (chi[i] - clo[i]);
      const int mode = static_cast<int>(rng() % 3);
      const std::uint64_t v1 = rng(), v2 = rng();
      const int switch_at = static_cast<int>(rng() % static_cast<std::uint64_t>(Q));
      auto vertex = [&](std::uint64_t bits) {
        Eigen::VectorXd w(n);
        for (int i = 0; i < n; ++i) w[i] = ((bits >> i) & 1u) ? s.w[i] : -s.w[i];
        return w;
      };
      for (int step = 0; step <= Q; ++step) {
        // Parts containing t_step: step / fine, and step / fine - 1 at a part boundary.
        for (int p = std::max(0, (step - 1) / s.fine); p <= std::min(P - 1, step / s.fine); ++p) {
          if (step < p * s.fine || step > (p + 1) * s.fine) continue;
          ++r.samples;
          for (int i = 0; i < n; ++i)
            if (x[i] < lo[p * n + i] || x[i] > hi[p * n + i]) {
              ++r.escapes;
              break;
            }
        }
        if (step == Q) break;
        Eigen::VectorXd w;
        if (mode == 0) {
          w.resize(n);
          for (int i = 0; i < n; ++i) w[i] = s.w[i] * (2 * unit(rng) - 1);
        } else {
          w = (mode == 1 || step < switch_at) ? vertex(v1) : vertex(v2);
        }
        x = integrate_period(f, x, u.data(), s.tau / Q, 1, [&](int) { return w; });
      }
    }
  }
  return r;
}

EnclosureSetup unicycle(const Dynamics& f) {
  return {&f, {-1, -1, -2}, {0.025, 0.025, 0.03}, {0.0, 0.025, 0.025}, {-2.4, -2.4}, {2.4, 2.4}, {0.3, 0.3},
          {0, 0, -3.2}, {10, 10, 3.2}};
}
EnclosureSetup cartpole(const Dynamics& f) {
  return {&f, {-0.195, -1.99, 1.20, -5.44}, {0.015, 0.035, 0.016, 0.064}, {0, 0.05, 0, 0}, {-7}, {7}, {0.2},
          {0, -1.5, 1.8, -3}, {5, 3, 4.4, 3}};
}
EnclosureSetup double_integrator(const Dynamics& f) {
  return {&f, {3, -3}, {0.01, 0.015}, {0, 0.1}, {-3}, {3}, {0.1}, {3.5, -2.5}, {8.5, 1.5}};
}
EnclosureSetup pendulum(const Dynamics& f) {
  return {&f, {-4, -4}, {0.01, 0.01}, {0, 0.01}, {-4}, {4}, {0.25}, {-0.5, -3}, {3.8, 3}};
}

void expect_sound(EnclosureSetup s) {
  const Result r = sample(s);
  EXPECT_GE(r.samples, 1000000);
  EXPECT_EQ(r.escapes, 0);
  EXPECT_LT(r.unbounded, s.cells / 10);
}

void expect_shrunk_leaks(EnclosureSetup s) {
  s.shrink = 0.1;
  s.cells = 60;
  s.samples_per_cell = 200;
  const Result r = sample(s);
  EXPECT_GT(r.escapes, 0) << "an enclosure 10% smaller than computed held every sample: the sampler is too weak";
}

}  // namespace

TEST(PeriodEnclosure, Unicycle) {
  models::Unicycle f;
  expect_sound(unicycle(f));
}
TEST(PeriodEnclosure, UnicycleShrunkLeaks) {
  models::Unicycle f;
  expect_shrunk_leaks(unicycle(f));
}
TEST(PeriodEnclosure, CartPole) {
  models::CartPole f;
  expect_sound(cartpole(f));
}
TEST(PeriodEnclosure, CartPoleShrunkLeaks) {
  models::CartPole f;
  expect_shrunk_leaks(cartpole(f));
}
TEST(PeriodEnclosure, DoubleIntegrator) {
  models::DoubleIntegrator f;
  expect_sound(double_integrator(f));
}
TEST(PeriodEnclosure, DoubleIntegratorShrunkLeaks) {
  models::DoubleIntegrator f;
  expect_shrunk_leaks(double_integrator(f));
}
TEST(PeriodEnclosure, Pendulum) {
  models::Pendulum f;
  expect_sound(pendulum(f));
}
TEST(PeriodEnclosure, PendulumShrunkLeaks) {
  models::Pendulum f;
  expect_shrunk_leaks(pendulum(f));
}
// One part and many parts are sound too (the option changes tightness only), and more parts
// give tighter boxes.
TEST(PeriodEnclosure, PartsChangeTightnessOnly) {
  models::Unicycle f;
  for (int parts : {1, 2, 8}) {
    EnclosureSetup s = unicycle(f);
    s.parts = parts;
    s.fine = 40 / parts;
    s.cells = 60;
    s.samples_per_cell = 200;
    EXPECT_EQ(sample(s).escapes, 0) << parts << " parts";
  }
}

// The enclosures a synthesized controller stores (hulls over a step's winning cells, shared
// over the coordinates the field does not read): every state of closed-loop runs from winning
// cells of step 0, at every fine substep, inside the enclosure of its time.
namespace {

void expect_closed_loop_inside(TrackingProblem p, double shrink, bool expect_escape) {
  const auto r = AbcdTracker().track(p, TrackOptions{});
  ASSERT_EQ(r.status, TrackerStatus::ControllerFound) << r.message;
  const Controller& c = *r.controller;
  const auto& enc = c.period_enclosures();
  const int T = c.horizon(), n = p.dynamics->state_dim();
  ASSERT_EQ(static_cast<int>(enc.size()), T * r.stats.enclosure_substeps);
  const int P = r.stats.enclosure_substeps, fine = 5, Q = P * fine;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  long long samples = 0, escapes = 0;
  const auto& grid = dynamic_cast<const GridController&>(c);
  for (int run = 0; run < 40; ++run) {
    Eigen::VectorXd x = p.nominal.x[0];
    for (int i = 0; i < n; ++i) x[i] += p.tube.eps[i] * (2 * unit(rng) - 1);
    if (!grid.winning(x.data(), 0)) continue;
    for (int k = 0; k < T; ++k) {
      Eigen::VectorXd u(p.dynamics->input_dim());
      ASSERT_EQ(c.input(x.data(), k, u.data()), ControlStatus::Ok) << "run " << run << " step " << k;
      const std::uint64_t bits = rng();
      for (int q = 0; q <= Q; ++q) {
        for (int part = std::max(0, (q - 1) / fine); part <= std::min(P - 1, q / fine); ++part) {
          if (q < part * fine || q > (part + 1) * fine) continue;
          const PeriodEnclosure& e = enc[static_cast<size_t>(k * P + part)];
          ++samples;
          for (int i = 0; i < n; ++i) {
            const double rad = 0.5 * (e.state.hi[i] - e.state.lo[i]);
            if (x[i] < e.state.lo[i] + shrink * rad || x[i] > e.state.hi[i] - shrink * rad) {
              ++escapes;
              break;
            }
          }
        }
        if (q == Q) break;
        Eigen::VectorXd w(n);
        const int mode = run % 3;
        for (int i = 0; i < n; ++i)
          w[i] = mode == 0 ? p.tube.w[i] * (2 * unit(rng) - 1)
                           : ((((mode == 1 ? bits : rng()) >> i) & 1u) ? p.tube.w[i] : -p.tube.w[i]);
        x = integrate_period(*p.dynamics, x, u.data(), p.tau / Q, 1, [&](int) { return w; });
      }
    }
  }
  EXPECT_GT(samples, 1000);
  if (expect_escape)
    EXPECT_GT(escapes, 0) << "stored enclosures cut by " << shrink << " held every closed-loop state";
  else
    EXPECT_EQ(escapes, 0);
}

}  // namespace

TEST(PeriodEnclosure, StoredEnclosuresHoldTheClosedLoopDrone) {
  expect_closed_loop_inside(scenarios::drone(30), 0.0, false);
}
TEST(PeriodEnclosure, StoredEnclosuresShrunkLeakDrone) {
  expect_closed_loop_inside(scenarios::drone(30), 0.1, true);
}
TEST(PeriodEnclosure, StoredEnclosuresHoldTheClosedLoopVehicle) {
  expect_closed_loop_inside(scenarios::vehicle(), 0.0, false);
}
// No coordinate is invariant: cells are enclosed in blocks (enclosure_block).
TEST(PeriodEnclosure, StoredEnclosuresHoldTheClosedLoopPendulum) {
  expect_closed_loop_inside(scenarios::pendulum(60), 0.0, false);
}
// Three coordinates in blocks, one invariant (the trolley position).
TEST(PeriodEnclosure, StoredEnclosuresHoldTheClosedLoopCrane) {
  expect_closed_loop_inside(scenarios::crane(4), 0.0, false);
}
