#include <dlfcn.h>
#include <malloc.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <fstream>
#include <sstream>
#include <thread>

#include "funnel_scenarios.hpp"
#include "funnel_tracker.hpp"
#include "marsyn/plugin.hpp"
#include "membership.hpp"

// glibc's own allocator (mallinfo2 from 2.33), not a sanitizer's.
#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer) || __has_feature(thread_sanitizer)
#define MARSYN_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define MARSYN_SANITIZED 1
#endif
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33)) && !defined(MARSYN_SANITIZED)
#define MARSYN_PLAIN_GLIBC_MALLOC 1
#else
#define MARSYN_PLAIN_GLIBC_MALLOC 0
#endif

namespace marsyn::funnel {
namespace {

std::shared_ptr<const FunnelController> unicycle_controller() {
  static const auto c = [] {
    // Zonotope sets: the membership tests below need them (the default stores parallelotopes).
    Params zonotopes;
    zonotopes.set("verified_set", std::string("zonotope"));
    const TrackResult r = FunnelTracker(zonotopes).track(testing::unicycle(30), {});
    EXPECT_EQ(r.status, TrackerStatus::ControllerFound) << r.message;
    return std::dynamic_pointer_cast<const FunnelController>(r.controller);
  }();
  return c;
}

std::string temp_file(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("marsyn_funnel_" + std::to_string(::getpid()) + "_" + name)).string();
}

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

TEST(FunnelController, FileRoundTripIsByteIdenticalAndAnswersAlike) {
  const auto c = unicycle_controller();
  ASSERT_TRUE(c);
  const std::string a = temp_file("a.ctl"), b = temp_file("b.ctl");
  c->write(a);
  const auto back = FunnelTracker().read_controller(a);
  back->write(b);
  EXPECT_EQ(slurp(a), slurp(b));
  // Small: nominal, gains and an order-8 zonotope (n x 8n, 576 bytes here) per step, 46.6 KB.
  EXPECT_LT(slurp(a).size(), 50'000u);
  const FunnelData& d = c->data();
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int s = 0; s < 2000; ++s) {
    const int k = s % d.horizon();
    std::vector<double> x(3), u1(2), u2(2);
    for (int i = 0; i < 3; ++i) x[i] = d.x_nom[k][i] + 1.2 * d.eps[i] * U(rng);
    const ControlStatus s1 = c->input(x.data(), k, u1.data()), s2 = back->input(x.data(), k, u2.data());
    ASSERT_EQ(s1, s2);
    if (s1 == ControlStatus::Ok) EXPECT_EQ(u1, u2);
  }
  EXPECT_EQ(back->period_enclosures().size(), c->period_enclosures().size());
  std::filesystem::remove(a);
  std::filesystem::remove(b);
}

// The zonotope test as it was before the least-norm proposal: the simplex's coefficients, in the
// cube, with the residual within tol.
bool in_zonotope_by_simplex(const StepSet& s, int n, const double* x) {
  const int p = s.generators;
  std::vector<double> d(n), xi(p);
  for (int j = 0; j < n; ++j) d[j] = x[j] - s.c[j];
  zonotope_coefficients(s.S.data(), n, p, d.data(), xi.data());
  for (int j = 0; j < p; ++j)
    if (!(std::fabs(xi[j]) <= 1.0)) return false;
  for (int i = 0; i < n; ++i) {
    double r = -d[i];
    for (int j = 0; j < p; ++j) r += s.S[static_cast<size_t>(j) * n + i] * xi[j];
    if (!(std::fabs(r) <= s.tol[i])) return false;
  }
  return true;
}

// The least-norm coefficients are a cheaper proposal, not a new rule: on states c + G xi with xi
// a little beyond the cube (inside and outside V_k) in_set answers exactly as the simplex alone,
// and most accepted states never reach the simplex.
TEST(FunnelController, TheLeastNormProposalAcceptsExactlyWhatTheSimplexAccepts) {
  const auto c = unicycle_controller();
  const FunnelData& d = c->data();
  std::mt19937_64 rng(7);
  long zonotope_steps = 0, inside = 0, outside = 0, by_least_norm = 0;
  for (int k = 1; k <= d.horizon(); ++k) {
    const StepSet& s = d.sets[k];
    if (s.kind != kZonotope) continue;
    ++zonotope_steps;
    ASSERT_FALSE(c->least_norm(k).empty()) << "step " << k;
    for (int t = 0; t < 400; ++t) {
      std::vector<double> x(d.n), xi(s.generators), dx(d.n);
      // c + G xi with xi a little beyond the cube: inside, outside, and near the faces.
      // Every other sample a vertex of the cube scaled by 0.8..1.3 (outside beyond about 1).
      std::uniform_real_distribution<double> coefficient(-1.15, 1.15), scale(0.8, 1.3);
      const double lambda = scale(rng);
      for (int j = 0; j < s.generators; ++j) xi[j] = t % 2 ? coefficient(rng) : lambda * (rng() % 2 ? 1.0 : -1.0);
      for (int i = 0; i < d.n; ++i) {
        x[i] = s.c[i];
        for (int j = 0; j < s.generators; ++j) x[i] += s.S[static_cast<size_t>(j) * d.n + i] * xi[j];
        dx[i] = x[i] - s.c[i];
      }
      bool in_box = true;
      for (int i = 0; i < d.n; ++i) in_box = in_box && x[i] >= s.lo[i] && x[i] <= s.hi[i];
      const bool expected = in_box && in_zonotope_by_simplex(s, d.n, x.data());
      ASSERT_EQ(c->in_set(x.data(), k), expected) << "step " << k << ", sample " << t;
      (expected ? inside : outside) += 1;
      least_norm_coefficients(c->least_norm(k).data(), d.n, s.generators, dx.data(), xi.data());
      bool cube = true;
      for (double v : xi) cube = cube && std::fabs(v) <= 1.0;
      by_least_norm += expected && cube;
    }
  }
  ASSERT_GT(zonotope_steps, 0);
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 300);
  EXPECT_GT(by_least_norm, inside / 2) << "the least-norm proposal rarely lies in the cube";
}

TEST(FunnelController, StatusesOutsideTheSetAndTheHorizon) {
  const auto c = unicycle_controller();
  ASSERT_TRUE(c);
  const FunnelData& d = c->data();
  double u[2];
  EXPECT_EQ(c->input(d.x_nom[0].data(), 0, u), ControlStatus::Ok);
  EXPECT_EQ(c->input(d.x_nom[0].data(), -1, u), ControlStatus::OutsideHorizon);
  EXPECT_EQ(c->input(d.x_nom[0].data(), d.horizon(), u), ControlStatus::OutsideHorizon);
  std::vector<double> far = d.x_nom[3];
  far[0] += 2 * d.eps[0];
  EXPECT_EQ(c->input(far.data(), 3, u), ControlStatus::OutsideDomain);
  std::vector<double> nan = d.x_nom[3];
  nan[1] = std::nan("");
  EXPECT_EQ(c->input(nan.data(), 3, u), ControlStatus::OutsideDomain);
  // At the nominal the input is the nominal input.
  EXPECT_EQ(c->input(d.x_nom[5].data(), 5, u), ControlStatus::Ok);
  EXPECT_DOUBLE_EQ(u[0], d.u_nom[5][0]);
  EXPECT_DOUBLE_EQ(u[1], d.u_nom[5][1]);
}

// What `check` predicts the tracking stage keeps (TrackerAssessment::kept_bytes) holds the
// controller as the allocator holds it: heap_bytes models glibc's blocks, and a copy of the
// controller takes that much from malloc (mallinfo2), so neither figure is a guess.
TEST(FunnelController, TheKeptBytesBoundHoldsWhatTheAllocatorKeeps) {
  Params defaults;
  const TrackResult r = FunnelTracker(defaults).track(testing::unicycle(30), {});
  ASSERT_EQ(r.status, TrackerStatus::ControllerFound) << r.message;
  const auto parallelotopes = std::dynamic_pointer_cast<const FunnelController>(r.controller);
  for (const auto& c : {parallelotopes, unicycle_controller()}) {
    ASSERT_TRUE(c);
    const FunnelData& d = c->data();
    const double model = heap_bytes(*c);
#if MARSYN_PLAIN_GLIBC_MALLOC  // a sanitizer's allocator keeps its own books: mallinfo2 does not see them
    // Copied on a thread of its own: its allocator cache starts empty, so every block is new.
    std::unique_ptr<FunnelController> copy;
    std::size_t before = 0, after = 0;
    std::thread([&] {
      // The thread's arena and cache come with its first block: made before counting, kept after.
      auto* first = static_cast<char*>(std::malloc(64));
      before = mallinfo2().uordblks;
      copy = std::make_unique<FunnelController>(d);
      after = mallinfo2().uordblks;
      std::free(first);
    }).join();
    // Within 3 % and the few KiB of bookkeeping a thread's arena adds as it grows.
    const double copied = heap_bytes(*copy);  // the copy's vectors hold no spare room
    EXPECT_NEAR(static_cast<double>(after) - static_cast<double>(before), copied, 0.03 * copied + 4096)
        << "heap_bytes does not count what malloc gives";
#endif
    // The bound the assessment gives (the tracker's defaults: 8 enclosures per step, order-8 sets).
    const double bound = kept_bytes_bound(d.n, d.m, d.horizon(), 8, 8 * d.n);
    EXPECT_LE(model, bound);
    EXPECT_GT(model, 0.5 * bound) << "a bound this loose says little";
    // Each part is counted: 10 % less of what a step keeps and the bound no longer holds the zonotope sets.
    if (d.sets.back().kind == kZonotope) EXPECT_GT(model, 0.9 * bound) << model << " of " << bound;
  }
}

// The run's stop request ends the verification at the step it is at (the time limit of
// `marsyn solve` is kept to within a step), and one that never fires changes nothing.
TEST(FunnelController, AStopRequestEndsTheVerificationAtOnce) {
  const TrackingProblem p = testing::unicycle(30);
  TrackOptions o;
  int polls = 0;
  o.stop = [&] { return ++polls > 10; };  // within the first verification
  const TrackResult r = FunnelTracker().track(p, o);
  EXPECT_EQ(r.status, TrackerStatus::ResourceLimit) << r.message;
  EXPECT_NE(r.message.find("stopped by the run after "), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("in verification 1"), std::string::npos) << r.message;
  EXPECT_FALSE(r.controller);
  EXPECT_EQ(polls, 11) << "polled again after it said stop";

  o.stop = [] { return false; };
  const TrackResult whole = FunnelTracker().track(p, o);
  EXPECT_EQ(whole.status, TrackerStatus::ControllerFound) << whole.message;
}

TEST(FunnelController, CorruptFilesAreRefusedWithTheReason) {
  const auto c = unicycle_controller();
  ASSERT_TRUE(c);
  const std::string good = serialize(c->data());
  auto refused = [](const std::string& bytes) -> std::string {
    try {
      deserialize(bytes, "x.ctl");
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  };
  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  EXPECT_NE(refused(flipped).find("checksum"), std::string::npos);
  EXPECT_NE(refused(good.substr(0, good.size() - 3)).find("size"), std::string::npos);
  std::string magic = good;
  magic[6] = 'C';  // an abcd controller's magic
  EXPECT_NE(refused(magic).find("not a marsyn funnel controller"), std::string::npos);
  EXPECT_NE(refused("").find("bad magic"), std::string::npos);
  EXPECT_EQ(refused(good), "");
}

TEST(FunnelController, PluginLibraryHasOneTrackerEntry) {
  void* lib = dlopen(MARSYN_TRACKER_FUNNEL_MODULE, RTLD_NOW | RTLD_LOCAL);
  ASSERT_TRUE(lib) << dlerror();
  auto entry = reinterpret_cast<const marsyn_plugin_manifest* (*)()>(dlsym(lib, "marsyn_plugin_entry_point"));
  ASSERT_TRUE(entry);
  const marsyn_plugin_manifest* m = entry();
  EXPECT_EQ(m->api_version, MARSYN_PLUGIN_API_VERSION);
  ASSERT_EQ(m->entry_count, 1u);
  EXPECT_STREQ(m->entries[0].kind, "tracker");
  EXPECT_STREQ(m->entries[0].name, "funnel");
  Params bad;
  bad.set("substeps", 12L);  // not a multiple of 8
  EXPECT_THROW(m->entries[0].create(bad), ParamError);
  auto* t = static_cast<Tracker*>(m->entries[0].create(Params{}));
  EXPECT_EQ(t->name(), "funnel");
  delete t;
  // The library stays loaded: the tracker's vtable lives in it.
}

}  // namespace
}  // namespace marsyn::funnel
