// The dense check's broad phase against the all-pairs check (issue 24): the running minima, the
// state where they fall and the requirement named there must be bit for bit SpecMonitor::step's,
// and the adversary's target the full search's, on random teams and on near misses built to sit
// just inside what the broad phase may skip.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "marsyn/core/plugins/plugin_registry.hpp"
#include "marsyn/core/verification/broad_phase.hpp"
#include "marsyn/core/verification/closed_loop.hpp"
#include "marsyn/core/verification/spec_monitor.hpp"

namespace {

using Eigen::Vector2d;
using Point = marsyn::planning::Point;
using Eigen::VectorXd;

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Unicycles: the workspace point is the state's (x, y), so a team is a list of points.
struct Team {
  marsyn::PluginRegistry registry;
  marsyn::Problem pb;

  int dim = 2;
  // dim 3: the workspace is (x, y, theta) read as a point in space (geometry only), and the
  // obstacles are prisms, some bounded in z.
  Team(int n, std::mt19937_64& rng, int obstacles, bool inf, int formation, int dim = 2) : dim(dim) {
    std::uniform_real_distribution<double> c(-10, 10), r(0.3, 2.0);
    for (int i = 0; i < n; ++i) {
      marsyn::AgentSpec a;
      a.name = "a" + std::to_string(i);
      a.dynamics_type = "unicycle";
      a.dynamics = registry.create<marsyn::Dynamics>("unicycle");
      a.x0 = VectorXd::Zero(3);
      a.goal = {VectorXd::Constant(3, -100), VectorXd::Constant(3, 100)};
      a.state_bounds = a.goal;
      a.input_bounds = {VectorXd::Constant(2, -2), VectorXd::Constant(2, 2)};
      a.tube.w = VectorXd::Constant(3, 0.2);
      a.tube.eps = VectorXd::Constant(3, 1.0);
      a.workspace.index = dim == 3 ? std::vector<int>{0, 1, 2} : std::vector<int>{0, 1};
      a.workspace.offset = std::vector<double>(static_cast<size_t>(dim), 0.0);
      pb.agents.push_back(a);
    }
    for (int o = 0; o < obstacles; ++o) {
      const Vector2d m(c(rng), c(rng));
      const double hx = r(rng), hy = r(rng);
      marsyn::Obstacle ob;
      ob.name = "o" + std::to_string(o);
      ob.vertices = {m + Vector2d(-hx, -hy), m + Vector2d(hx, -hy), m + Vector2d(hx, hy), m + Vector2d(-hx, hy)};
      if (dim == 3 && o % 3 != 2) {  // every third one full height
        const double z = c(rng), hz = r(rng);
        ob.z_lo = z - hz;
        ob.z_hi = o % 3 == 1 ? std::numeric_limits<double>::infinity() : z + hz;
      }
      pb.obstacles.push_back(ob);
    }
    for (int q = 0; q < formation && n > 1; ++q) pb.formation.push_back({q % n, (q + 1) % n, 2.0, 0.5});
    pb.delta = 0.25;
    pb.delta_norm = inf ? marsyn::Norm::Inf : marsyn::Norm::Two;
    pb.tau = 0.1;
    pb.workspace_dim = dim;
  }
  // The agents' states from their points (the first N; further bodies' points follow from them).
  VectorXd state(const std::vector<Point>& p) const {
    const std::size_t n = std::min(p.size(), pb.agents.size());
    VectorXd x = VectorXd::Zero(3 * static_cast<Eigen::Index>(n));
    for (std::size_t i = 0; i < n; ++i)
      x.segment(3 * static_cast<Eigen::Index>(i), dim) = p[i].head(dim);
    return x;
  }
};

// Folds a sequence of point sets both ways and checks every state: the minima bit for bit,
// whether the smallest part fell, and its name.
void expect_same_folds(const Team& t, const std::vector<std::vector<Point>>& states) {
  const marsyn::SpecMonitor monitor(t.pb);
  marsyn::BroadPhase broad(t.pb);
  marsyn::StepMargins fast, slow;
  for (std::size_t k = 0; k < states.size(); ++k) {
    std::string name;
    const marsyn::StepMargins m = monitor.step(t.state(states[k]), &name);
    const double before = slow.min();
    slow = {std::min(slow.obstacle, m.obstacle), std::min(slow.collision, m.collision), std::min(slow.formation, m.formation)};
    broad.update(states[k]);
    marsyn::planning::Requirement q{marsyn::planning::Requirement::Obstacle, -1, -1};
    const bool fell = broad.accumulate(fast, &q);
    ASSERT_TRUE(same_bits(fast.obstacle, slow.obstacle)) << "state " << k;
    ASSERT_TRUE(same_bits(fast.collision, slow.collision)) << "state " << k;
    ASSERT_TRUE(same_bits(fast.formation, slow.formation)) << "state " << k;
    ASSERT_EQ(fell, slow.min() < before) << "state " << k;
    if (fell) ASSERT_EQ(q.name(t.pb), name) << "state " << k;
    // From nothing, a fold is the state's own margins (the kept runs' plots).
    marsyn::StepMargins own;
    broad.accumulate(own, nullptr);
    ASSERT_TRUE(same_bits(own.obstacle, m.obstacle) && same_bits(own.collision, m.collision) &&
                same_bits(own.formation, m.formation))
        << "state " << k;
  }
}

// Random walks of n agents from scattered starts: the running minima fall now and then, as in a run.
std::vector<std::vector<Point>> random_walks(std::mt19937_64& rng, int n, int steps, int dim = 2) {
  std::normal_distribution<double> step(0.0, 0.15);
  std::uniform_real_distribution<double> start(-12, 12);
  const double zs = dim == 3 ? 1.0 : 0.0;
  std::vector<Point> p(static_cast<size_t>(n));
  for (auto& q : p) q = {start(rng), start(rng), 0};
  if (dim == 3)
    for (auto& q : p) q.z() = start(rng);
  std::vector<std::vector<Point>> states;
  for (int k = 0; k < steps; ++k) {
    for (auto& q : p) q += Point(step(rng), step(rng), zs * step(rng));
    states.push_back(p);
  }
  return states;
}

// The same, a window of `width` states at a time (BroadPhase::window, as between two samples).
void expect_same_window_folds(const Team& t, const std::vector<std::vector<Point>>& states, int width) {
  const marsyn::SpecMonitor monitor(t.pb);
  marsyn::BroadPhase broad(t.pb);
  marsyn::StepMargins fast, slow;
  for (std::size_t k0 = 0; k0 < states.size(); k0 += static_cast<size_t>(width)) {
    const int count = std::min(width, static_cast<int>(states.size() - k0));
    const std::vector<std::vector<Point>> window(states.begin() + static_cast<long>(k0),
                                                    states.begin() + static_cast<long>(k0) + count);
    broad.window(window, count, fast, {-1, false});
    for (int s = 0; s < count; ++s) {
      const std::size_t k = k0 + static_cast<size_t>(s);
      std::string name;
      const marsyn::StepMargins m = monitor.step(t.state(states[k]), &name);
      const double before = slow.min();
      slow = {std::min(slow.obstacle, m.obstacle), std::min(slow.collision, m.collision), std::min(slow.formation, m.formation)};
      marsyn::planning::Requirement q{marsyn::planning::Requirement::Obstacle, -1, -1};
      const bool fell = broad.accumulate_window(s, fast, &q);
      ASSERT_TRUE(same_bits(fast.obstacle, slow.obstacle)) << "state " << k;
      ASSERT_TRUE(same_bits(fast.collision, slow.collision)) << "state " << k;
      ASSERT_TRUE(same_bits(fast.formation, slow.formation)) << "state " << k;
      ASSERT_EQ(fell, slow.min() < before) << "state " << k;
      if (fell) ASSERT_EQ(q.name(t.pb), name) << "state " << k;
    }
  }
}

TEST(BroadPhase, WindowsGiveTheAllPairsMinimaBitForBit) {
  std::mt19937_64 rng(25);
  for (int team = 0; team < 100; ++team) {
    const int n = 2 + static_cast<int>(rng() % 40);
    const Team t(n, rng, static_cast<int>(rng() % 4), team % 2 == 0, static_cast<int>(rng() % 3));
    const std::vector<std::vector<Point>> states = random_walks(rng, n, 76);
    SCOPED_TRACE("team " + std::to_string(team) + " of " + std::to_string(n) + " agents");
    expect_same_window_folds(t, states, 1 + team % 19);
  }
}

TEST(BroadPhase, AWindowsNearMissInItsMiddleIsNotSkipped) {
  // The first window sets the minima (agents 0 and 1 apart by 3 along y, agent 2 two metres
  // right of the block); in the second, agents 3 and 4 and agent 2 come a hair inside those at
  // the window's middle state only, far at its first and last.
  std::mt19937_64 rng(4);
  for (bool inf : {true, false}) {
    Team t(5, rng, 0, inf, 0);
    t.pb.obstacles.push_back({"block", {{0, 0}, {4, 0}, {4, 4}, {0, 4}}});
    const std::vector<Point> a = {{20, 0, 0}, {20, 3, 0}, {6, 2, 0}, {-20, 10, 0}, {-20, 20, 0}};
    std::vector<std::vector<Point>> states(10, a);
    for (int s = 5; s < 10; ++s) {
      states[static_cast<size_t>(s)][2] = {9, 2, 0};
      states[static_cast<size_t>(s)][4] = {-20, 30, 0};
    }
    states[7][2] = {6 - 1e-12, 2, 0};
    states[7][4] = {-20, 13 - 1e-12, 0};
    expect_same_window_folds(t, states, 5);
    marsyn::BroadPhase broad(t.pb);
    marsyn::StepMargins m;
    broad.window(states, 5, m, {-1, false});
    for (int s = 0; s < 5; ++s) broad.accumulate_window(s, m, nullptr);
    const std::vector<std::vector<Point>> second(states.begin() + 5, states.end());
    broad.window(second, 5, m, {-1, false});
    std::vector<std::string> names;
    for (int s = 0; s < 5; ++s) {
      marsyn::planning::Requirement q{};
      names.push_back(broad.accumulate_window(s, m, &q) ? q.name(t.pb) : "");
    }
    EXPECT_EQ(names, (std::vector<std::string>{"", "", "obstacle block vs a2", "", ""}));
    EXPECT_EQ(m.collision, 3 - 1e-12 - t.pb.delta);
  }
}

// A team flying in formation: agents on a circle of radius 1.5, every pair a formation pair at
// its starting distance with tolerance mu, the whole team drifting together (a shared step per
// state) with each agent jittering on its own, so that the pairs' distances wander near lambda
// and the formation minimum falls now and then.
std::vector<std::vector<Point>> formation_walks(Team& t, std::mt19937_64& rng, int steps, double mu) {
  const int n = static_cast<int>(t.pb.agents.size());
  std::vector<Point> p(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::acos(-1.0) * i / n;
    p[static_cast<size_t>(i)] = {1.5 * std::cos(a), 1.5 * std::sin(a), 0};
  }
  t.pb.formation.clear();
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      t.pb.formation.push_back({i, j, (p[static_cast<size_t>(i)] - p[static_cast<size_t>(j)]).norm(), mu});
  std::normal_distribution<double> jitter(0.0, 0.02), drift(0.0, 0.1);
  std::vector<std::vector<Point>> states;
  for (int k = 0; k < steps; ++k) {
    const Point shared(drift(rng), drift(rng), 0);
    for (auto& q : p) q += shared + Point(jitter(rng), jitter(rng), 0);
    states.push_back(p);
  }
  return states;
}

TEST(BroadPhase, FormationTeamsGiveTheAllPairsMinimaBitForBit) {
  std::mt19937_64 rng(53);
  for (int team = 0; team < 60; ++team) {
    const int n = 2 + static_cast<int>(rng() % 8);
    Team t(n, rng, static_cast<int>(rng() % 2), team % 2 == 0, 0);
    const std::vector<std::vector<Point>> states = formation_walks(t, rng, 120, 0.2 + 0.1 * (team % 5));
    SCOPED_TRACE("team " + std::to_string(team) + " of " + std::to_string(n) + " agents");
    expect_same_folds(t, states);
    expect_same_window_folds(t, states, 1 + team % 19);
  }
}

TEST(BroadPhase, AFormationsNearMissInAWindowsMiddleIsNotSkipped) {
  // Two agents 2 apart (lambda 2, mu 0.5): the first window sets the formation minimum at
  // 0.5 - 0.3 (3 of its states 2.3 apart); in the second the pair is exactly lambda apart but at
  // the middle state, 2.3 + 1e-12 apart (then 1.7 - 1e-12: a hair short), the team moving along x.
  std::mt19937_64 rng(8);
  for (bool inf : {true, false}) {
    Team t(2, rng, 0, inf, 0);
    t.pb.pairwise_collision = false;
    t.pb.formation.push_back({0, 1, 2.0, 0.5});
    std::vector<std::vector<Point>> states;
    for (int s = 0; s < 10; ++s) states.push_back({{0.1 * s, 0, 0}, {0.1 * s + (s < 3 ? 2.3 : 2.0), 0, 0}});
    states[7][1].x() = states[7][0].x() + 2.3 + 1e-12;
    std::vector<std::vector<Point>> shorter = states;
    shorter[7][1].x() = shorter[7][0].x() + 1.7 - 1e-12;
    for (const auto& run : {states, shorter}) {
      expect_same_window_folds(t, run, 5);
      marsyn::BroadPhase broad(t.pb);
      marsyn::StepMargins m;
      std::vector<std::string> names;
      for (int w = 0; w < 2; ++w) {
        const std::vector<std::vector<Point>> window(run.begin() + 5 * w, run.begin() + 5 * w + 5);
        broad.window(window, 5, m, {-1, false});
        for (int s = 0; s < 5; ++s) {
          marsyn::planning::Requirement q{};
          names.push_back(broad.accumulate_window(s, m, &q) ? q.name(t.pb) : "");
        }
      }
      EXPECT_EQ(names[7], "formation a0 - a1");
      EXPECT_LT(m.formation, 0.2);
    }
  }
}

TEST(BroadPhase, RandomTeamsGiveTheAllPairsMinimaBitForBit) {
  std::mt19937_64 rng(24);
  for (int team = 0; team < 100; ++team) {
    const int n = 2 + static_cast<int>(rng() % 40);
    const Team t(n, rng, static_cast<int>(rng() % 4), team % 2 == 0, static_cast<int>(rng() % 3));
    const std::vector<std::vector<Point>> states = random_walks(rng, n, 60);
    SCOPED_TRACE("team " + std::to_string(team) + " of " + std::to_string(n) + " agents");
    expect_same_folds(t, states);
  }
}

// Bodies of their own size (issue 51): a pair keeps delta plus both radii, so the sweep's reach
// must hold the two largest; with the team's delta alone it skips pairs whose bodies meet.
TEST(BroadPhase, TeamsWithBodiesGiveTheAllPairsMinimaBitForBit) {
  std::mt19937_64 rng(51);
  std::uniform_real_distribution<double> radius(0.0, 2.0);
  for (int team = 0; team < 60; ++team) {
    const int n = 2 + static_cast<int>(rng() % 30);
    Team t(n, rng, static_cast<int>(rng() % 4), team % 2 == 0, 0);
    for (auto& a : t.pb.agents) a.radius = rng() % 4 == 0 ? 0.0 : radius(rng);
    const std::vector<std::vector<Point>> states = random_walks(rng, n, 40);
    SCOPED_TRACE("team " + std::to_string(team) + " of " + std::to_string(n) + " agents");
    expect_same_folds(t, states);
    expect_same_window_folds(t, states, 5);
  }
}

// Agents with further bodies (issue 51): each a point of the agent's state at an offset, so a
// team's states are its agents' points and the bodies are body slots after them. The broad phase
// over the slots (never a pair of one agent's own bodies) gives the all-pairs minima bit for bit.
// Up to two further bodies per agent, each at a random planar offset from its point, in agent
// order (the loader's).
void add_bodies(Team& t, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> radius(0.0, 1.0), offset(-1.5, 1.5);
  for (int i = 0; i < static_cast<int>(t.pb.agents.size()); ++i)
    for (int k = 0; k < static_cast<int>(rng() % 3); ++k) {
      marsyn::ExtraBody e;
      e.agent = i;
      e.body = "b" + std::to_string(k);
      e.spec = t.pb.agents[static_cast<std::size_t>(i)];
      e.spec.name = e.spec.name + "'s " + e.body;
      e.spec.workspace.offset.assign(e.spec.workspace.index.size(), 0.0);
      e.spec.workspace.offset[0] = offset(rng);
      e.spec.workspace.offset[1] = offset(rng);
      e.spec.radius = radius(rng);
      t.pb.extra_bodies.push_back(e);
    }
}

TEST(BroadPhase, AgentsWithSeveralBodiesGiveTheAllPairsMinimaBitForBit) {
  std::mt19937_64 rng(52);
  for (int team = 0; team < 40; ++team) {
    const int n = 2 + static_cast<int>(rng() % 20);
    Team t(n, rng, static_cast<int>(rng() % 4), team % 2 == 0, 0);
    add_bodies(t, rng);
    const std::vector<std::vector<Point>> agents = random_walks(rng, n, 30);
    std::vector<std::vector<Point>> states;
    for (const auto& p : agents) {
      std::vector<Point> q = p;
      for (const auto& e : t.pb.extra_bodies)
        q.push_back(p[static_cast<std::size_t>(e.agent)] + Point(e.spec.workspace.offset[0], e.spec.workspace.offset[1], 0));
      states.push_back(q);
    }
    SCOPED_TRACE("team " + std::to_string(team) + " of " + std::to_string(n) + " agents, " +
                 std::to_string(t.pb.extra_bodies.size()) + " further bodies");
    expect_same_folds(t, states);
    expect_same_window_folds(t, states, 5);
  }
}

// Folds the states with the broad phase alone; the requirement named at each state where the
// smallest part fell ("" where it did not).
std::vector<std::string> falls(const Team& t, const std::vector<std::vector<Point>>& states) {
  marsyn::BroadPhase broad(t.pb);
  marsyn::StepMargins m;
  std::vector<std::string> out;
  for (const auto& p : states) {
    marsyn::planning::Requirement q{};
    broad.update(p);
    out.push_back(broad.accumulate(m, &q) ? q.name(t.pb) : "");
  }
  return out;
}

TEST(BroadPhase, NearMissesBetweenAgentsAreNotSkipped) {
  std::mt19937_64 rng(1);
  for (bool inf : {true, false}) {
    const Team t(6, rng, 0, inf, 0);
    // The first state sets the collision minimum at 3 - delta (agents 0 and 1, apart along y);
    // in the second, agents 2 and 5 come a hair inside that along x, with agents 3 and 4 between
    // them in the x order, so the sweep must run past both to find the pair.
    const std::vector<Point> a = {{20, 0, 0}, {20, 3, 0}, {-20, 10, 0}, {-15, -10, 0}, {-13, 10, 0}, {-30, -10, 0}};
    std::vector<Point> b = a;
    b[3] = {-19.5, -10, 0};
    b[4] = {-18, 5, 0};
    b[5] = {-17 - 1e-12, 10, 0};
    expect_same_folds(t, {a, b});
    EXPECT_EQ(falls(t, {a, b}), (std::vector<std::string>{"collision a0 vs a1", "collision a2 vs a5"}));
  }
}

TEST(BroadPhase, NearMissesOfObstaclesAreNotSkipped) {
  std::mt19937_64 rng(2);
  for (bool inf : {true, false}) {
    Team t(3, rng, 0, inf, 0);
    t.pb.pairwise_collision = false;
    t.pb.obstacles.push_back({"block", {{0, 0}, {4, 0}, {4, 4}, {0, 4}}});
    // Agent 0 one metre right of the block, then a hair nearer, off the row it was on; then
    // agents 1 and 2 inside the block, the second deeper: no box bound holds inside the box.
    const std::vector<Point> s1 = {{5, 2, 0}, {30, 30, 0}, {-30, 30, 0}};
    std::vector<Point> s2 = s1, s3, s4;
    s2[0] = {5 - 1e-12, 2.5, 0};
    s3 = s2;
    s3[1] = {1, 1, 0};
    s4 = s3;
    s4[2] = {2, 2, 0};
    expect_same_folds(t, {s1, s2, s3, s4});
    EXPECT_EQ(falls(t, {s1, s2, s3, s4}), (std::vector<std::string>{"obstacle block vs a0", "obstacle block vs a0",
                                                                     "obstacle block vs a1", "obstacle block vs a2"}));
  }
}

// The adversary's target for every agent of a state, by the broad phase and by the full search
// (the same point bit for bit, or neither finds one).
void expect_same_targets(const Team& t, const std::vector<Point>& p) {
  marsyn::BroadPhase broad(t.pb);
  broad.update(p);
  for (int i = 0; i < static_cast<int>(p.size()); ++i) {
    Point fast(7, 7, 7), slow(7, 7, 7);
    const bool f = broad.nearest_target(i, fast), s = marsyn::nearest_by_search(t.pb, i, p, slow);
    ASSERT_EQ(f, s) << "agent " << i;
    if (f) ASSERT_TRUE(same_bits(fast.x(), slow.x()) && same_bits(fast.y(), slow.y())) << "agent " << i;
  }
}

TEST(BroadPhase, NearestTargetIsTheFullSearchsOnRandomTeams) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> at(-12, 12);
  for (int team = 0; team < 100; ++team) {
    Team t(1 + static_cast<int>(rng() % 30), rng, static_cast<int>(rng() % 4), team % 2 == 0, 0);
    t.pb.pairwise_collision = team % 5 != 0;
    std::vector<Point> p(t.pb.agents.size());
    for (auto& q : p) q = {at(rng), at(rng), 0};
    // Some agents on a lattice: equal distances to several agents, ties broken by index.
    for (std::size_t i = 0; i < p.size(); i += 3) p[i] = {std::round(p[i].x()), std::round(p[i].y()), 0};
    SCOPED_TRACE("team " + std::to_string(team));
    expect_same_targets(t, p);
  }
}

// One broad phase kept across the states of a motion (its lists and last answers carried from
// state to state, as in a run): every agent's target is the full search's at every state.
void expect_same_targets_along(const Team& t, const std::vector<std::vector<Point>>& states) {
  marsyn::BroadPhase broad(t.pb);
  for (std::size_t s = 0; s < states.size(); ++s) {
    const std::vector<Point>& p = states[s];
    broad.update(p);
    for (int i = 0; i < static_cast<int>(p.size()); ++i) {
      Point fast(7, 7, 7), slow(7, 7, 7);
      const bool f = broad.nearest_target(i, fast), sr = marsyn::nearest_by_search(t.pb, i, p, slow);
      ASSERT_EQ(f, sr) << "state " << s << ", agent " << i;
      if (f) ASSERT_TRUE(same_bits(fast.x(), slow.x()) && same_bits(fast.y(), slow.y())) << "state " << s << ", agent " << i;
    }
  }
}

TEST(BroadPhase, NearestTargetFollowsMovingTeams) {
  // Random teams drifting for 300 states (steps up to 0.05, new velocities now and then): the
  // last answer kept while it provably stays nearest must be the search's at every state.
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> at(-6, 6), vel(-0.05, 0.05);
  for (int team = 0; team < 30; ++team) {
    Team t(2 + static_cast<int>(rng() % 25), rng, static_cast<int>(rng() % 3), team % 2 == 0, 0);
    std::vector<Point> p(t.pb.agents.size()), v(p.size());
    for (auto& q : p) q = {at(rng), at(rng), 0};
    for (auto& q : v) q = {vel(rng), vel(rng), 0};
    std::vector<std::vector<Point>> states;
    for (int s = 0; s < 300; ++s) {
      if (s % 50 == 49)
        for (auto& q : v) q = {vel(rng), vel(rng), 0};
      for (std::size_t i = 0; i < p.size(); ++i) p[i] += v[i];
      states.push_back(p);
    }
    SCOPED_TRACE("team " + std::to_string(team));
    expect_same_targets_along(t, states);
  }
  // Agent 2 overtakes agent 1 as agent 0's nearest by a thousandth per state, tying it once
  // (agent 1 wins the tie by its index), while agent 1 stays put: fails when the last answer is
  // kept with no bound on how far the others moved.
  Team t(3, rng, 0, false, 0);
  std::vector<std::vector<Point>> states;
  for (int s = 0; s <= 200; ++s) states.push_back({{0, 0, 0}, {1, 0, 0}, {-1.1 + 0.001 * s, 0, 0}});
  states[100][2] = {-1, 0, 0};
  expect_same_targets_along(t, states);
}

TEST(BroadPhase, NearestTargetKeepsTwoNearlyTiedCandidates) {
  // Agents 1 and 2 on either side of agent 0, nearly tied (the symmetric neighbours of a circle
  // swap), taking turns as the nearer by a millionth; agent 3 approaches from 1.5 away by a
  // thousandth per state and overtakes both: fails when the two candidates are kept with no bound
  // on how far the third has moved, or when the nearer of the two is misjudged.
  std::mt19937_64 rng(17);
  Team t(4, rng, 0, false, 0);
  std::vector<std::vector<Point>> states;
  for (int s = 0; s <= 700; ++s) {
    const double wobble = (s % 2 == 0 ? 1e-6 : -1e-6) * (s % 7 == 3 ? 0.0 : 1.0);  // exact ties now and then
    states.push_back({{0, 0, 0}, {1 + wobble, 0, 0}, {-1, 0, 0}, {0, 1.5 - 0.001 * s, 0}});
  }
  expect_same_targets_along(t, states);
}

TEST(BroadPhase, NearestTargetBreaksARoundingTieByIndex) {
  // Two candidates whose sums of squares differ in the last bit while their distances (the
  // square roots distance2() takes) are equal: the tie goes to the smaller index, as in the full
  // search. Agent 2's sum is the smaller one: fails when the candidates are ordered by their sums
  // with no margin for the root's rounding.
  std::mt19937_64 rng(19);
  Team t(4, rng, 0, false, 0);
  const Point one(0.5, 0.7, 0);
  Point two(-0.7, 0.5, 0);
  auto sum = [](const Point& e) { return e.x() * e.x() + e.y() * e.y(); };
  auto ulps = [](double v, int k) {
    for (; k > 0; --k) v = std::nextafter(v, 10.0);
    for (; k < 0; ++k) v = std::nextafter(v, -10.0);
    return v;
  };
  bool found = false;
  for (int dx = -20; dx <= 20 && !found; ++dx)
    for (int dy = -20; dy <= 20 && !found; ++dy) {
      const Point c(ulps(-0.7, dx), ulps(0.5, dy), 0);
      if (sum(c) < sum(one) && marsyn::planning::distance2(c) == marsyn::planning::distance2(one)) {
        two = c;
        found = true;
      }
    }
  ASSERT_TRUE(found);
  std::vector<std::vector<Point>> states(4, std::vector<Point>{{0, 0, 0}, one, two, {3, 3, 0}});
  expect_same_targets_along(t, states);
  marsyn::BroadPhase broad(t.pb);
  for (const auto& p : states) {
    broad.update(p);
    Point target;
    ASSERT_TRUE(broad.nearest_target(0, target));
    EXPECT_EQ(target, one);
  }
}

TEST(BroadPhase, AnObstacleAsNearAsTheNearestAgentIsTheTarget) {
  // Agent 0 is 1 m from agent 1 and 1 m from the block's face, whose bounding box is as near as
  // the block itself: the obstacle must still be searched (and wins the tie); then a hair
  // farther, the agent wins.
  std::mt19937_64 rng(3);
  for (bool inf : {true, false}) {
    Team t(2, rng, 0, inf, 0);
    t.pb.obstacles.push_back({"block", {{0, 0}, {4, 0}, {4, 4}, {0, 4}}});
    expect_same_targets(t, {{5, 2, 0}, {5, 3, 0}});
    marsyn::BroadPhase broad(t.pb);
    std::vector<Point> p = {{5, 2, 0}, {5, 3, 0}};
    broad.update(p);
    Point target;
    ASSERT_TRUE(broad.nearest_target(0, target));
    EXPECT_EQ(target, Point(4, 2, 0));
    p[1] = {5, 3 - 1e-12, 0};
    broad.update(p);
    ASSERT_TRUE(broad.nearest_target(0, target));
    EXPECT_EQ(target, p[1]);
    expect_same_targets(t, p);
  }
}

TEST(BroadPhase, TiedObstaclesGiveTheFirstByIndexWhateverTheirBoxes) {
  // Agent 0 at the origin, 2 sqrt(2) from a square (obstacle 0, its corner at (-2, -2)) and, just
  // as far, from a triangle's long side (obstacle 1, nearest point (2, 2)) whose bounding box is
  // much nearer (sqrt(2)): the triangle is searched first, and the square, as near, still wins.
  std::mt19937_64 rng(43);
  for (bool inf : {true, false}) {
    Team t(2, rng, 0, inf, 0);
    t.pb.obstacles.push_back({"square", {{-4, -4}, {-2, -4}, {-2, -2}, {-4, -2}}});
    t.pb.obstacles.push_back({"triangle", {{3, 1}, {3, 3}, {1, 3}}});
    const std::vector<Point> p = {{0, 0, 0}, {30, 30, 0}};
    expect_same_targets(t, p);
    marsyn::BroadPhase broad(t.pb);
    broad.update(p);
    Point target;
    ASSERT_TRUE(broad.nearest_target(0, target));
    EXPECT_EQ(target, Point(-2, -2, 0));
  }
}

TEST(BroadPhase, AnObstacleAsNearAsAKeptNearestAgentIsTheTarget) {
  // Agent 0 and agent 1 (1 m above it) approach the block's face together, so that agent 0's
  // nearest agent is kept from state to state (decided without its distance) while the face comes
  // from 1.5 m to 0.5 m, as near as the agent exactly at one state: the obstacle must be searched
  // then and win the tie. Fails when the obstacle's squared bound is compared against anything
  // but the nearest agent's squared distance.
  std::mt19937_64 rng(23);
  for (bool inf : {true, false}) {
    Team t(3, rng, 0, inf, 0);
    t.pb.obstacles.push_back({"block", {{0, 0}, {4, 0}, {4, 4}, {0, 4}}});
    for (double gap : {1.0, 0.5}) {
      std::vector<std::vector<Point>> states;
      for (int s = 0; s <= 200; ++s) {
        const double d = s == 100 ? gap : gap + 0.5 - 0.005 * s;
        states.push_back({{4 + d, 2, 0}, {4 + d, 2 + gap, 0}, {-20, -20, 0}});
      }
      SCOPED_TRACE("gap " + std::to_string(gap));
      expect_same_targets_along(t, states);
      marsyn::BroadPhase broad(t.pb);
      for (int s = 0; s <= 100; ++s) {
        broad.update(states[static_cast<size_t>(s)]);
        Point target;
        ASSERT_TRUE(broad.nearest_target(0, target));
        if (s == 100) EXPECT_EQ(target, Point(4, 2, 0));
      }
    }
  }
}

TEST(BroadPhase, PointsOutOfRangeGiveTheAllPairsAnswers) {
  // A point whose squares overflow (1e200) and one not finite at all: the broad phase falls back
  // to visiting everything, and still answers as the all-pairs check and the full search.
  std::mt19937_64 rng(29);
  for (bool inf : {true, false}) {
    Team t(6, rng, 2, inf, 1);
    std::vector<std::vector<Point>> states = random_walks(rng, 6, 30);
    states[10][2] = {1e200, -1e200, 0};
    states[11][2] = {1e200, 1e200, 0};
    states[20][4] = {std::numeric_limits<double>::quiet_NaN(), 0, 0};
    expect_same_targets_along(t, states);
    expect_same_folds(t, std::vector<std::vector<Point>>(states.begin(), states.begin() + 15));
  }
}

// Random starts in [-spread, spread]^3 for the team's agents and random inputs for `steps` steps:
// the open loop the end-to-end comparisons run (the nominal states are the starts).
std::vector<marsyn::NominalTrajectory> random_open_loop(Team& t, std::mt19937_64& rng, double spread, int steps) {
  std::uniform_real_distribution<double> start(-spread, spread), in(-1.5, 1.5);
  std::vector<marsyn::NominalTrajectory> nominal;
  for (auto& a : t.pb.agents) {
    a.x0 = VectorXd(3);
    a.x0 << start(rng), start(rng), start(rng);
    marsyn::NominalTrajectory nt;
    nt.agent = a.name;
    for (int k = 0; k <= steps; ++k) nt.x.push_back(a.x0);
    for (int k = 0; k < steps; ++k) nt.u.push_back((VectorXd(2) << in(rng), in(rng)).finished());
    nominal.push_back(nt);
  }
  return nominal;
}

// The verification runs' own path (no dense states kept: the dense check a period at a time,
// boxes found as the substeps' points are written, the runs in one batch) against the all-pairs
// reference, one run per mode: the same minima bit for bit, the same requirement or stage named at
// the same time. Returns the reference runs.
std::vector<marsyn::ClosedLoopRun> expect_same_windowed_runs(const Team& t, const std::vector<marsyn::NominalTrajectory>& nominal,
                                                             const marsyn::SpecMonitor& monitor,
                                                             const std::vector<marsyn::DisturbanceMode>& modes, int seed) {
  marsyn::SimulationSetup fast{&t.pb, nominal, {}, 20, &monitor};
  fast.keep_states = false;
  marsyn::SimulationSetup slow = fast;
  slow.all_pairs = true;
  std::vector<marsyn::Scenario> batch;
  for (auto mode : modes) batch.push_back({mode, static_cast<std::uint64_t>(seed) + batch.size(), 0});
  const std::vector<marsyn::ClosedLoopRun> f = marsyn::simulate(fast, batch), s = marsyn::simulate(slow, batch);
  for (std::size_t r = 0; r < batch.size(); ++r) {
    SCOPED_TRACE("run " + std::to_string(r));
    EXPECT_TRUE(same_bits(f[r].between.obstacle, s[r].between.obstacle));
    EXPECT_TRUE(same_bits(f[r].between.collision, s[r].between.collision));
    EXPECT_TRUE(same_bits(f[r].between.formation, s[r].between.formation));
    EXPECT_TRUE(same_bits(f[r].between.stage, s[r].between.stage));
    EXPECT_EQ(f[r].between_worst, s[r].between_worst);
    EXPECT_TRUE(same_bits(f[r].between_worst_t, s[r].between_worst_t));
    EXPECT_TRUE(same_bits(f[r].sampled.min_margin, s[r].sampled.min_margin));
    EXPECT_EQ(f[r].sampled.worst, s[r].sampled.worst);
    EXPECT_TRUE(same_bits(f[r].max_tube_excess, s[r].max_tube_excess));
  }
  return s;
}

TEST(BroadPhase, AdversaryTargetsTheSameAsTheFullSearch) {
  // End to end: open loop under the adversary (re-chosen at every substep), all pairs vs the
  // broad phase: the same trajectories (so the same targets) and the same margins.
  std::mt19937_64 rng(7);
  for (int team = 0; team < 6; ++team) {
    Team t(8 + 4 * team, rng, team % 3, team % 2 == 1, team % 2);
    const std::vector<marsyn::NominalTrajectory> nominal = random_open_loop(t, rng, 6.0, 15);
    const marsyn::SpecMonitor monitor(t.pb);
    marsyn::SimulationSetup fast{&t.pb, nominal, {}, 20, &monitor};
    fast.keep_dense = true;
    marsyn::SimulationSetup slow = fast;
    slow.all_pairs = true;
    for (auto mode : {marsyn::DisturbanceMode::Adversarial, marsyn::DisturbanceMode::UniformRandom}) {
      const marsyn::Scenario sc{mode, static_cast<std::uint64_t>(team), 0};
      const marsyn::ClosedLoopRun f = marsyn::simulate(fast, sc), s = marsyn::simulate(slow, sc);
      SCOPED_TRACE("team " + std::to_string(team) + ", " + marsyn::to_string(mode));
      ASSERT_EQ(f.states.size(), s.states.size());
      for (std::size_t k = 0; k < f.states.size(); ++k) ASSERT_TRUE(f.states[k] == s.states[k]) << "step " << k;
      EXPECT_TRUE(same_bits(f.between.min(), s.between.min()));
      ASSERT_EQ(f.dense_margins.size(), s.dense_margins.size());
      for (std::size_t q = 0; q < f.dense_margins.size(); ++q)
        ASSERT_TRUE(same_bits(f.dense_margins[q].min(), s.dense_margins[q].min())) << "dense state " << q;
      EXPECT_EQ(f.between_worst, s.between_worst);
      EXPECT_TRUE(same_bits(f.between_worst_t, s.between_worst_t));
      EXPECT_TRUE(same_bits(f.sampled.min_margin, s.sampled.min_margin));
      EXPECT_EQ(f.sampled.worst, s.sampled.worst);
      // And the samples as SpecMonitor::evaluate judges the kept states.
      const marsyn::SpecEvaluation ev = monitor.evaluate(s.states);
      EXPECT_TRUE(same_bits(f.sampled.min_margin, ev.min_margin));
      EXPECT_EQ(f.sampled.worst, ev.worst);
    }
  }
}

// Convex polygons with slanted edges in place of the team's boxes (3 to 7 vertices on a rotated
// ellipse, counter-clockwise as the loader stores them): inside its bounding box only the edges'
// half-planes bound an obstacle's margin.
void slant(Team& t, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> turn(0, 2 * std::acos(-1.0)), r(0.3, 2.5);
  for (auto& ob : t.pb.obstacles) {
    const Vector2d m = 0.5 * (ob.vertices[0] + ob.vertices[2]);
    const double rx = r(rng), ry = r(rng), phi = turn(rng);
    std::vector<double> at(3 + rng() % 5);
    for (double& a : at) a = turn(rng);
    std::sort(at.begin(), at.end());
    ob.vertices.clear();
    for (double a : at) {
      const Vector2d e(rx * std::cos(a), ry * std::sin(a));
      ob.vertices.push_back(m + Vector2d(std::cos(phi) * e.x() - std::sin(phi) * e.y(), std::sin(phi) * e.x() + std::cos(phi) * e.y()));
    }
  }
}

// Eight random teams' windowed runs against the all-pairs reference (expect_same_windowed_runs),
// with the obstacles made slanted polygons (slant) or left boxes.
void expect_same_windowed_teams(std::uint64_t seed, bool slanted) {
  std::mt19937_64 rng(seed);
  for (int team = 0; team < 8; ++team) {
    const int dim = team % 4 == 3 ? 3 : 2;
    Team t(6 + 3 * team, rng, team % 4 + (slanted ? 1 : 0), team % 2 == 1, team % 3, dim);
    if (slanted) slant(t, rng);
    const std::vector<marsyn::NominalTrajectory> nominal = random_open_loop(t, rng, 5.0, 12);
    const marsyn::SpecMonitor monitor(t.pb);
    SCOPED_TRACE("team " + std::to_string(team));
    expect_same_windowed_runs(t, nominal, monitor,
                              {marsyn::DisturbanceMode::Adversarial, marsyn::DisturbanceMode::UniformRandom,
                               marsyn::DisturbanceMode::VertexSwitching, marsyn::DisturbanceMode::Adversarial,
                               marsyn::DisturbanceMode::PaperConstant, marsyn::DisturbanceMode::None},
                              team * 10);
  }
}

TEST(BroadPhase, WindowedRunsGiveTheAllPairsMargins) {
  // The verification runs' own path (no dense states kept: the dense check a period at a time,
  // boxes found as the substeps' points are written, several runs in one batch) against the
  // all-pairs reference: the same minima bit for bit, the same requirement named at the same time.
  expect_same_windowed_teams(31, false);
}

TEST(BroadPhase, WindowedRunsOfAgentsWithSeveralBodiesGiveTheAllPairsMargins) {
  // The runs' own path reads every body's point from its agent's state (a map per body) in the
  // windows; the reference evaluates every requirement of every body at each substep.
  std::mt19937_64 rng(53);
  for (int team = 0; team < 6; ++team) {
    Team t(4 + 2 * team, rng, team % 3 + 1, team % 2 == 1, 0);
    add_bodies(t, rng);
    const std::vector<marsyn::NominalTrajectory> nominal = random_open_loop(t, rng, 5.0, 12);
    const marsyn::SpecMonitor monitor(t.pb);
    SCOPED_TRACE("team " + std::to_string(team) + ", " + std::to_string(t.pb.extra_bodies.size()) + " further bodies");
    expect_same_windowed_runs(t, nominal, monitor,
                              {marsyn::DisturbanceMode::Adversarial, marsyn::DisturbanceMode::UniformRandom,
                               marsyn::DisturbanceMode::VertexSwitching, marsyn::DisturbanceMode::None},
                              team * 10);
  }
}

TEST(BroadPhase, WindowedMissionRunsGiveTheAllPairsMargins) {
  // Missions: stages dwelling over periods (box regions in state coordinates and polygons in the
  // workspace, some too small for the random motion, some large) are folded substep by substep
  // after the requirements in the windowed runs; the reference checks every pair and every stage
  // at each substep. The same minima, stage part included, and the same requirement or stage
  // named at the same time.
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> c(-6, 6), half(0.5, 12);
  int stage_named = 0, other_named = 0;
  for (int team = 0; team < 10; ++team) {
    Team t(5 + 2 * team, rng, team % 4, team % 2 == 1, team % 3);
    for (std::size_t i = 0; i < t.pb.agents.size(); i += 1 + static_cast<std::size_t>(team % 2)) {
      const int stages = 1 + static_cast<int>(rng() % 2);
      for (int q = 0; q < stages; ++q) {
        marsyn::MissionStage st;
        st.name = "s" + std::to_string(q);
        const Vector2d m(c(rng), c(rng));
        const double hx = half(rng), hy = half(rng);
        if (rng() % 2) {
          st.polygon = {m + Vector2d(-hx, -hy), m + Vector2d(hx, -hy), m + Vector2d(hx, hy), m + Vector2d(-hx, hy)};
        } else {
          st.box = {(VectorXd(3) << m.x() - hx, m.y() - hy, -100).finished(), (VectorXd(3) << m.x() + hx, m.y() + hy, 100).finished()};
        }
        st.not_before = 1 + 5 * q + static_cast<int>(rng() % 3);
        st.dwell = 1 + static_cast<int>(rng() % 3);
        t.pb.agents[i].stages.push_back(st);
      }
    }
    const int steps = 14;
    const std::vector<marsyn::NominalTrajectory> nominal = random_open_loop(t, rng, 5.0, steps);
    const marsyn::SpecMonitor monitor(t.pb, steps);
    ASSERT_TRUE(monitor.has_stages());
    SCOPED_TRACE("team " + std::to_string(team));
    for (const marsyn::ClosedLoopRun& s :
         expect_same_windowed_runs(t, nominal, monitor,
                                   {marsyn::DisturbanceMode::Adversarial, marsyn::DisturbanceMode::UniformRandom,
                                    marsyn::DisturbanceMode::VertexSwitching, marsyn::DisturbanceMode::None},
                                   team * 10))
      (s.between.stage == s.between.min() ? stage_named : other_named) += 1;
  }
  // Both kinds of outcome were compared: a stage lowest, and a requirement lowest.
  EXPECT_GT(stage_named, 3);
  EXPECT_GT(other_named, 3);
}

TEST(BroadPhase, AStagesDepthDippingInsideAPeriodIsNotSkipped) {
  // One unicycle spirals inside a square stage region it dwells in from step 1: constant turn
  // rate, speed growing step by step, so that its depth below the region's lower edge reaches a
  // new minimum each turn, a few per cent below the last and somewhere inside a period (the dense
  // check skips a depth only when it clears the minimum so far). The windowed runs against the
  // all-pairs reference, both norms, several centres.
  std::mt19937_64 rng(61);
  for (bool inf : {true, false})
    for (int c = 0; c < 4; ++c) {
      Team t(1, rng, 0, inf, 0);
      auto& a = t.pb.agents[0];
      a.x0 = (VectorXd(3) << 0.0, 0.1 * c, 0.0).finished();
      marsyn::MissionStage st;
      st.name = "spiral";
      st.polygon = {{-2, -0.6}, {2, -0.6}, {2, 2}, {-2, 2}};
      st.not_before = 1;
      st.dwell = 38;
      a.stages.push_back(st);
      marsyn::NominalTrajectory nt;
      nt.agent = a.name;
      for (int k = 0; k <= 40; ++k) nt.x.push_back(a.x0);
      for (int k = 0; k < 40; ++k) nt.u.push_back((VectorXd(2) << 0.4 + 0.02 * k + 0.05 * c, 5.0 + c).finished());
      const marsyn::SpecMonitor monitor(t.pb, 40);
      ASSERT_TRUE(monitor.has_stages());
      SCOPED_TRACE("centre " + std::to_string(c) + (inf ? ", inf-norm" : ", 2-norm"));
      const std::vector<marsyn::ClosedLoopRun> runs =
          expect_same_windowed_runs(t, {nt}, monitor, {marsyn::DisturbanceMode::None, marsyn::DisturbanceMode::UniformRandom}, c);
      EXPECT_EQ(runs[0].between_worst, "stage spiral of a0");
    }
}

TEST(BroadPhase, AWindowedRunsCrossingInsideAPeriodIsNotSkipped) {
  // Agent 0 drives at 2 m/s straight at agent 1, from 1 m away: 0.6 m at sample 2, 0.4 m at
  // sample 3, where it backs away, while agents 2 and 3 stand 0.5 m apart from the start. In the period between samples
  // 2 and 3 agent 0 starts farther than the running minimum's reach and ends nearer: only its box
  // over the whole period (its far side included) keeps the pair. In each of the four directions
  // (a box's every side), both norms: the windowed runs' minimum and name are the all-pairs ones.
  std::mt19937_64 rng(37);
  for (bool inf : {true, false})
    for (int dir = 0; dir < 4; ++dir) {
      Team t(4, rng, 0, inf, 0);
      const double th = dir * std::acos(-1.0) / 2;
      const Vector2d u(std::cos(th), std::sin(th)), at(1.5, -2.0);
      const Vector2d p0 = at - u, p2(8, 8), p3(8.5, 8);
      const Vector2d starts[4] = {p0, at, p2, p3};
      std::vector<marsyn::NominalTrajectory> nominal;
      for (int i = 0; i < 4; ++i) {
        auto& a = t.pb.agents[static_cast<size_t>(i)];
        a.x0 = (VectorXd(3) << starts[i].x(), starts[i].y(), i == 0 ? th : 0.0).finished();
        marsyn::NominalTrajectory nt;
        nt.agent = a.name;
        for (int k = 0; k <= 5; ++k) nt.x.push_back(a.x0);
        for (int k = 0; k < 5; ++k) nt.u.push_back((VectorXd(2) << (i == 0 ? (k < 3 ? 2.0 : -2.0) : 0.0), 0.0).finished());
        nominal.push_back(nt);
      }
      const marsyn::SpecMonitor monitor(t.pb);
      marsyn::SimulationSetup fast{&t.pb, nominal, {}, 20, &monitor};
      fast.keep_states = false;
      marsyn::SimulationSetup slow = fast;
      slow.all_pairs = true;
      const marsyn::Scenario sc{marsyn::DisturbanceMode::None, 1, 0};
      const marsyn::ClosedLoopRun f = marsyn::simulate(fast, sc), s = marsyn::simulate(slow, sc);
      SCOPED_TRACE("direction " + std::to_string(dir) + (inf ? ", inf-norm" : ", 2-norm"));
      EXPECT_EQ(s.between_worst, "collision a0 vs a1");
      EXPECT_LT(s.between.collision, 0.5 - t.pb.delta - 0.05);
      EXPECT_TRUE(same_bits(f.between.collision, s.between.collision));
      EXPECT_EQ(f.between_worst, s.between_worst);
      EXPECT_TRUE(same_bits(f.between_worst_t, s.between_worst_t));
    }
}

// Random walks that start near the obstacles (within 1.5 of a vertex), so that agents wander in
// and out of the polygons' bounding boxes beside the slanted edges.
std::vector<std::vector<Point>> walks_near_obstacles(const Team& t, std::mt19937_64& rng, int steps) {
  std::vector<std::vector<Point>> states = random_walks(rng, static_cast<int>(t.pb.agents.size()), steps, t.dim);
  std::uniform_real_distribution<double> off(-1.5, 1.5);
  for (std::size_t i = 0; i < t.pb.agents.size() && !t.pb.obstacles.empty(); ++i) {
    const auto& ob = t.pb.obstacles[i % t.pb.obstacles.size()];
    const Vector2d v = ob.vertices[rng() % ob.vertices.size()] + Vector2d(off(rng), off(rng));
    const Point shift(v.x() - states[0][i].x(), v.y() - states[0][i].y(), 0);
    for (auto& p : states) p[i] += shift;
  }
  return states;
}

TEST(BroadPhase, SlantedPolygonsGiveTheAllPairsMinimaBitForBit) {
  std::mt19937_64 rng(43);
  for (int team = 0; team < 100; ++team) {
    const int n = 2 + static_cast<int>(rng() % 20);
    Team t(n, rng, 1 + static_cast<int>(rng() % 4), team % 2 == 0, static_cast<int>(rng() % 3), team % 5 == 4 ? 3 : 2);
    slant(t, rng);
    const std::vector<std::vector<Point>> states = walks_near_obstacles(t, rng, 60);
    SCOPED_TRACE("team " + std::to_string(team) + " of " + std::to_string(n) + " agents");
    expect_same_folds(t, states);
    expect_same_window_folds(t, states, 1 + team % 19);
    expect_same_targets_along(t, states);
  }
}

TEST(BroadPhase, ANearMissOfASlantedEdgeInsideItsBoxIsNotSkipped) {
  // A triangle whose hypotenuse x + y = 4 crosses its bounding box [0, 4]^2. Agent 0 inside the
  // box beyond the hypotenuse at (2.5, 2.5) sets the obstacle minimum; then, elsewhere along the
  // edge, a hair nearer (its half-plane bound equals its distance there), then a little farther;
  // agent 1 stands far away. Only the nearer state lowers the minimum, and it must be seen.
  std::mt19937_64 rng(6);
  for (bool inf : {true, false}) {
    Team t(2, rng, 0, inf, 0);
    t.pb.pairwise_collision = false;
    t.pb.obstacles.push_back({"tri", {{0, 0}, {4, 0}, {0, 4}}});
    const std::vector<Point> a = {{2.5, 2.5, 0}, {30, 30, 0}};
    std::vector<Point> b = a, c = a;
    b[0] = {3.0 - 1e-12, 2.0, 0};
    c[0] = {3.05, 2.05, 0};
    expect_same_folds(t, {a, b, c});
    expect_same_window_folds(t, {a, b, c}, 3);
    EXPECT_EQ(falls(t, {a, b, c}), (std::vector<std::string>{"obstacle tri vs a0", "obstacle tri vs a0", ""}));
  }
}

TEST(BroadPhase, WindowedFormationRunsGiveTheAllPairsMargins) {
  // A team in formation (agents on a circle, every pair at its starting distance within mu) driven
  // by one shared random input sequence, so that it moves together while the disturbances bend
  // the pairs' distances: the windowed runs against the all-pairs reference.
  std::mt19937_64 rng(59);
  std::uniform_real_distribution<double> in(-1.5, 1.5);
  for (int team = 0; team < 6; ++team) {
    const int n = 3 + team;
    Team t(n, rng, team % 2, team % 2 == 1, 0);
    const std::vector<std::vector<Point>> start = formation_walks(t, rng, 1, 0.15 + 0.05 * team);
    std::vector<VectorXd> inputs;
    for (int k = 0; k < 12; ++k) inputs.push_back((VectorXd(2) << in(rng), in(rng)).finished());
    std::vector<marsyn::NominalTrajectory> nominal;
    for (int i = 0; i < n; ++i) {
      auto& a = t.pb.agents[static_cast<size_t>(i)];
      a.x0 = (VectorXd(3) << start[0][static_cast<size_t>(i)].x(), start[0][static_cast<size_t>(i)].y(), 0.3).finished();
      marsyn::NominalTrajectory nt;
      nt.agent = a.name;
      for (int k = 0; k <= 12; ++k) nt.x.push_back(a.x0);
      nt.u = inputs;
      nominal.push_back(nt);
    }
    const marsyn::SpecMonitor monitor(t.pb);
    SCOPED_TRACE("team " + std::to_string(team));
    expect_same_windowed_runs(t, nominal, monitor,
                              {marsyn::DisturbanceMode::Adversarial, marsyn::DisturbanceMode::UniformRandom,
                               marsyn::DisturbanceMode::VertexSwitching, marsyn::DisturbanceMode::PaperConstant,
                               marsyn::DisturbanceMode::None},
                              team * 10 + 5);
  }
}

TEST(BroadPhase, WindowedRunsAmongSlantedPolygonsGiveTheAllPairsMargins) { expect_same_windowed_teams(47, true); }

}  // namespace

// A 3-D workspace: prisms (bounded, half-bounded and full-height), pairs and formations in
// space. The broad phase prunes on x-y alone, a lower bound of the 3-D distances, and must
// still give the all-pairs minima bit for bit.
TEST(BroadPhase, ThreeDTeamsGiveTheAllPairsMinimaBitForBit) {
  std::mt19937_64 rng(33);
  for (int team = 0; team < 60; ++team) {
    const int n = 2 + static_cast<int>(rng() % 30);
    const Team t(n, rng, static_cast<int>(rng() % 6), team % 2 == 0, static_cast<int>(rng() % 3), 3);
    const std::vector<std::vector<Point>> states = random_walks(rng, n, 50, 3);
    SCOPED_TRACE("team " + std::to_string(team) + " of " + std::to_string(n) + " agents");
    expect_same_folds(t, states);
    expect_same_window_folds(t, states, 1 + team % 11);
    for (std::size_t k = 0; k < states.size(); k += 10) expect_same_targets(t, states[k]);
  }
}

TEST(BroadPhase, APairApartInXYButNotInZIsNotSkipped) {
  // Two agents at the same x-y, 0.2 apart in z: in the plane they would coincide; in space their
  // margin is 0.2 - delta, and an agent under a prism's floor is as far as the gap below it.
  std::mt19937_64 rng(5);
  for (bool inf : {true, false}) {
    Team t(3, rng, 0, inf, 0, 3);
    marsyn::Obstacle slab;
    slab.name = "slab";
    slab.vertices = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
    slab.z_lo = 1.0;
    slab.z_hi = 2.0;
    t.pb.obstacles.push_back(slab);
    const std::vector<Point> a = {{10, 10, 0}, {10, 10, 0.2}, {2, 2, 0.5}};
    expect_same_folds(t, {a});
    const marsyn::SpecMonitor monitor(t.pb);
    const marsyn::StepMargins m = monitor.step(t.state(a));
    EXPECT_DOUBLE_EQ(m.collision, 0.2 - t.pb.delta);
    EXPECT_DOUBLE_EQ(m.obstacle, 0.5 - t.pb.delta);
  }
}
