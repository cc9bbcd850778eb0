// Randomized soundness of the funnel tracker: >= 1e6 closed-loop periods per model, from states
// of each step's verified set (vertices of the parallelotope favoured), under vertex, switching
// and random disturbances, must end in the next verified set and stay in their part's period
// enclosure at every fine step; the same samples against the sets shrunk by 10% must leak, so the
// test can fail and the sets are not loose by more than that.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <map>
#include <mutex>
#include <chrono>
#include <random>

#include "funnel_scenarios.hpp"
#include "funnel_tracker.hpp"
#include "membership.hpp"

namespace marsyn::funnel {
namespace {

using testing::scenario;

struct Tracked {
  TrackingProblem problem;
  TrackResult result;
};

// remainder_scale < 1: the second-order remainder shrunk (the test hook), to show leaks.
const Tracked& tracked(const std::string& name, double remainder_scale = 1.0) {
  static std::map<std::pair<std::string, double>, Tracked> cache;
  static std::mutex mu;
  std::lock_guard<std::mutex> lock(mu);
  auto it = cache.find({name, remainder_scale});
  if (it != cache.end()) return it->second;
  Tracked t;
  t.problem = scenario(name);
  FunnelTracker tracker;
  tracker.scale_remainder_for_tests(remainder_scale);
  t.result = tracker.track(t.problem, {});
  return cache.emplace(std::make_pair(name, remainder_scale), std::move(t)).first->second;
}

struct Counts {
  long samples = 0, outside_domain = 0, leaks = 0, shrunk_leaks = 0;
  long fine_states = 0, enclosure_leaks = 0, shrunk_enclosure_leaks = 0;
};

// x in V_k shrunk about its centre by `factor` (1: V_k itself, as the controller tests it).
bool in_scaled_set(const FunnelData& d, const double* x, int k, double factor) {
  const StepSet& s = d.sets[k];
  const int n = d.n;
  // The set's own shape is shrunk; its box (the eps-tube) only for the initial box, which is
  // the whole set there.
  const double box_factor = s.kind == kBox ? factor : 1.0;
  for (int j = 0; j < n; ++j) {
    const double mid = 0.5 * (s.lo[j] + s.hi[j]), half = 0.5 * (s.hi[j] - s.lo[j]) * box_factor;
    if (!(x[j] >= mid - half && x[j] <= mid + half)) return false;
  }
  if (s.kind == kBox) return true;
  if (s.kind == kZonotope) {
    // The zonotope shrunk about its centre: generators scaled by `factor`.
    const int p = s.generators;
    std::vector<double> G(s.S), d(n), xi(p);
    for (double& g : G) g *= factor;
    for (int j = 0; j < n; ++j) d[j] = x[j] - s.c[j];
    zonotope_coefficients(G.data(), n, p, d.data(), xi.data());
    for (int i = 0; i < n; ++i) {
      double r = -d[i];
      for (int j = 0; j < p; ++j) r += G[j * n + i] * xi[j];
      if (!(std::fabs(r) <= s.tol[i])) return false;
    }
    return true;
  }
  for (int i = 0; i < n; ++i) {
    double y = 0;
    for (int j = 0; j < n; ++j) y += s.S[i * n + j] * (x[j] - s.c[j]);
    if (!(std::fabs(y) <= factor)) return false;
  }
  return true;
}

Counts sample(const Tracked& t, long total, std::uint64_t seed) {
  const auto& ctrl = dynamic_cast<const FunnelController&>(*t.result.controller);
  const FunnelData& d = ctrl.data();
  const Dynamics& f = *t.problem.dynamics;
  const int n = d.n, m = d.m, T = d.horizon();
  const int P = static_cast<int>(d.enclosures.size()) / T;
  constexpr int kFine = 32, kPieces = 8;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1), U01(0, 1);
  Counts c;
  const long per_step = total / T + 1;
  std::vector<double> x(n), y(n), u(m), w(n), nxt(n);
  for (int k = 0; k < T; ++k) {
    Eigen::MatrixXd Tp;
    const StepSet& set = d.sets[k];
    if (set.kind == kParallelotope) {
      Eigen::MatrixXd S(n, n);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) S(i, j) = d.sets[k].S[i * n + j];
      Tp = S.inverse();
    }
    for (long s = 0; s < per_step; ++s) {
      // A state of V_k: a vertex-biased point of the parallelotope (or box), kept if accepted.
      bool found = false;
      for (int attempt = 0; attempt < 50 && !found; ++attempt) {
        for (int i = 0; i < n; ++i) y[i] = U01(rng) < 0.5 ? (U01(rng) < 0.5 ? -1.0 : 1.0) : U(rng);
        if (set.kind == kZonotope) {
          // A vertex-biased point of the zonotope c + G xi.
          std::vector<double> xi(set.generators);
          for (auto& v : xi) v = U01(rng) < 0.5 ? (U01(rng) < 0.5 ? -1.0 : 1.0) : U(rng);
          if (U01(rng) < 0.5) {
            // A vertex: the support point in a random direction a (xi_j = sign(g_j . a)). With
            // many generators random signs stay near the centre; vertices reach the boundary.
            std::vector<double> a(n);
            for (auto& v : a) v = U(rng);
            for (int j = 0; j < set.generators; ++j) {
              double dot = 0;
              for (int i = 0; i < n; ++i) dot += set.S[j * n + i] * a[i];
              xi[j] = dot >= 0 ? 1.0 : -1.0;
            }
          }
          for (int i = 0; i < n; ++i) {
            x[i] = set.c[i];
            for (int j = 0; j < set.generators; ++j) x[i] += set.S[j * n + i] * xi[j] * (1 - 1e-12);
          }
        } else if (Tp.size() == 0) {
          for (int i = 0; i < n; ++i) x[i] = 0.5 * (d.sets[k].lo[i] + d.sets[k].hi[i]) + 0.5 * y[i] * (d.sets[k].hi[i] - d.sets[k].lo[i]);
        } else {
          for (int i = 0; i < n; ++i) {
            x[i] = d.sets[k].c[i];
            for (int j = 0; j < n; ++j) x[i] += Tp(i, j) * y[j] * (1 - 1e-12);
          }
        }
        found = ctrl.in_set(x.data(), k);
      }
      if (!found) continue;
      ++c.samples;
      if (ctrl.input(x.data(), k, u.data()) != ControlStatus::Ok) {
        ++c.outside_domain;
        continue;
      }
      const int mode = static_cast<int>(U01(rng) * 3);
      for (int piece = 0; piece < kPieces; ++piece) {
        if (piece == 0 || mode == 1)
          for (int i = 0; i < n; ++i) w[i] = (U01(rng) < 0.5 ? -1 : 1) * d.w[i];
        if (mode == 2)
          for (int i = 0; i < n; ++i) w[i] = U(rng) * d.w[i];
        for (int q = 0; q < kFine / kPieces; ++q) {
          rk4_step<double>(f, x.data(), u.data(), w.data(), d.tau / kFine, 1, nxt.data());
          x = nxt;
          const int fine = piece * (kFine / kPieces) + q + 1;  // time fine / kFine of the period
          const int part = std::min(P - 1, fine * P / kFine);
          const PeriodEnclosure& e = d.enclosures[static_cast<std::size_t>(k) * P + part];
          ++c.fine_states;
          bool in = true, in_shrunk = true;
          for (int i = 0; i < n; ++i) {
            const double lo = e.state.lo[i], hi = e.state.hi[i], cut = 0.05 * (hi - lo);
            if (!(x[i] >= lo && x[i] <= hi)) in = false;
            if (!(x[i] >= lo + cut && x[i] <= hi - cut)) in_shrunk = false;
          }
          c.enclosure_leaks += !in;
          c.shrunk_enclosure_leaks += !in_shrunk;
        }
      }
      c.leaks += !ctrl.in_set(x.data(), k + 1);
      c.shrunk_leaks += !in_scaled_set(d, x.data(), k + 1, 0.9);
    }
  }
  return c;
}

class FunnelSoundness : public ::testing::TestWithParam<std::string> {};

TEST_P(FunnelSoundness, SuccessorsStayInTheNextVerifiedSet) {
  const Tracked& t = tracked(GetParam());
  ASSERT_EQ(t.result.status, TrackerStatus::ControllerFound) << t.result.message;
  // The 12-state quadrotor's order-8 sets have 64 generators: one membership test costs about
  // 0.7 ms there (Bland's rule): 1e5 samples took 97 s under load, 1e6 would take ~16 min.
  const long total = GetParam() == "quadrotor" ? 100'000 : 1'000'000;
  const Counts c = sample(t, total, 7);
  EXPECT_GE(c.samples, total);
  EXPECT_EQ(c.leaks, 0) << "of " << c.samples;
  EXPECT_EQ(c.enclosure_leaks, 0) << "of " << c.fine_states;
  // The same samples against sets 10% smaller: the test must be able to fail.
  EXPECT_GT(c.shrunk_leaks, c.samples / 100) << "the verified sets are more than 10% larger than the reachable states";
  EXPECT_GT(c.shrunk_enclosure_leaks, c.fine_states / 100);
  RecordProperty("shrunk_leaks", std::to_string(c.shrunk_leaks));
  long kinds[3] = {0, 0, 0};
  for (const auto& st : dynamic_cast<const FunnelController&>(*t.result.controller).data().sets) ++kinds[st.kind];
  std::printf("%s: sets: %ld box, %ld parallelotopes, %ld zonotopes\n", GetParam().c_str(), kinds[0], kinds[1], kinds[2]);
  EXPECT_GT(kinds[1] + kinds[2], 0);
  std::printf("%s: %ld samples, %ld leak the 10%%-shrunk sets, %ld of %ld fine states leak the shrunk enclosures (%s)\n",
              GetParam().c_str(), c.samples, c.shrunk_leaks, c.shrunk_enclosure_leaks, c.fine_states,
              t.result.message.c_str());
}

INSTANTIATE_TEST_SUITE_P(Models, FunnelSoundness,
                         ::testing::Values("unicycle", "unicycle_at_bound", "crane", "bicycle", "planar_quadrotor", "quadrotor"));

TEST(FunnelSoundness, TooLargeADisturbanceGivesNoController) {
  TrackingProblem p = scenario("unicycle");
  p.tube.w = p.tube.w * 0 + Eigen::VectorXd::Constant(3, 1.5);  // 1.5 units/s against a 0.2-wide tube
  const TrackResult r = FunnelTracker().track(p, {});
  EXPECT_EQ(r.status, TrackerStatus::NoController) << r.message;
  EXPECT_FALSE(r.controller);
  EXPECT_NE(r.message.find("eps-tube"), std::string::npos) << r.message;
}

TEST(FunnelSoundness, InitialSetMustFitTheTube) {
  const TrackingProblem p = scenario("unicycle");
  AgentSpec a;
  a.x0 = p.nominal.x[0];
  a.tube.eps = p.tube.eps;
  a.input_bounds = p.input_bounds;
  Params big;
  big.set("initial_radius", std::vector<double>{0.1, 0.25, 0.1});  // 0.25 > eps_y = 0.2
  const TrackerAssessment r = FunnelTracker(big).assess(a, 60, 0.1);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.field, "initial_radius");
  EXPECT_EQ(r.coordinate, 1);
  EXPECT_EQ(FunnelTracker(big).track(p, {}).status, TrackerStatus::NoController);
  Params wrong;
  wrong.set("initial_radius", std::vector<double>{0.1, 0.1});
  EXPECT_FALSE(FunnelTracker(wrong).assess(a, 60, 0.1).ok);
  EXPECT_EQ(FunnelTracker(wrong).track(p, {}).status, TrackerStatus::InvalidInput);
  EXPECT_TRUE(FunnelTracker().assess(a, 60, 0.1).ok);
}

}  // namespace
}  // namespace marsyn::funnel
#include "lqr.hpp"
