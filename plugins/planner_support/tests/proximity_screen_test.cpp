// The broad phase over pair and obstacle rows: a row it leaves out must be satisfied at the state
// it was asked about (for both norms, with buffers and the clearance between the samples), and it
// must leave rows out where agents are far apart. A reach or an obstacle box shrunk by 10% leaves
// violated rows out: the checks below catch it, so they can fail.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "marsyn/core/planning/constraints.hpp"
#include "marsyn/planner_support/proximity_screen.hpp"
#include "test_problems.hpp"

using namespace marsyn;
using planner_support::ProximityScreen;

namespace {

// N unicycles scattered in a square of side `side` (a random team).
Problem team(int N, double side, Norm norm, std::mt19937& rng) {
  Problem p = testproblems::unicycle_crossing(40);
  const AgentSpec proto = p.agents[0];
  p.agents.clear();
  std::uniform_real_distribution<double> pos(0.0, side);
  for (int i = 0; i < N; ++i) {
    AgentSpec a = proto;
    a.name = "u" + std::to_string(i);
    a.x0 = Eigen::Vector3d(pos(rng), pos(rng), 0.0);
    a.state_bounds = {Eigen::Vector3d(-1, -1, -7), Eigen::Vector3d(side + 1, side + 1, 7)};
    const Eigen::Vector3d g(pos(rng), pos(rng), 0.0), r(0.4, 0.4, 10.0);
    a.goal = {g - r, g + r};
    a.tube.eps = Eigen::Vector3d(0.05 + 0.1 * i / N, 0.2 - 0.1 * i / N, 0.1);
    p.agents.push_back(a);
  }
  p.delta_norm = norm;
  p.guarantee = Guarantee::Continuous;
  return p;
}

// The same constraint with its reach (and its decay rate) scaled: what a too-small reach, or a
// rate too high (which widens a level's screen too little), would let through.
class ScaledReach final : public Constraint {
 public:
  ScaledReach(const Constraint& c, double s, double decay = 1.0) : c_(c), s_(s), decay_(decay) {}
  std::string name() const override { return c_.name(); }
  int size() const override { return c_.size(); }
  ConstraintStage stage() const override { return c_.stage(); }
  const std::vector<int>& support() const override { return c_.support(); }
  void evaluate(const double* x, double* g, double* jac) const override { c_.evaluate(x, g, jac); }
  double pair_reach() const override { return s_ * c_.pair_reach(); }
  bool clear_outside(double lo[2], double hi[2]) const override { return c_.clear_outside(lo, hi); }
  double reach_decay() const override { return decay_ * c_.reach_decay(); }

 private:
  const Constraint& c_;
  double s_, decay_;
};

// The screen's list as one flag per constraint; the list must be strictly increasing (the order
// a solver visits the whole list in).
std::vector<char> near_flags(const ProximityScreen& screen, const double* x, std::size_t size,
                             ProximityScreen::Buffers* buffers = nullptr, double level = 0.0) {
  std::vector<int> list;
  ProximityScreen::Buffers own;
  if (buffers) screen.near(x, list, *buffers, level);
  else if (level > 0) screen.near(x, list, own, level);
  else screen.near(x, list);
  std::vector<char> flags(size, 0);
  for (std::size_t i = 0; i < list.size(); ++i) {
    EXPECT_TRUE(list[i] >= 0 && static_cast<std::size_t>(list[i]) < size) << list[i];
    if (i > 0) EXPECT_LT(list[i - 1], list[i]);
    flags[static_cast<std::size_t>(list[i])] = 1;
  }
  return flags;
}

struct Tally {
  long skipped = 0, near = 0, violated_skipped = 0;
};

// Random product states around the agents' start points (so that many pairs sit near their
// reach); for every row the screen leaves out (at `level`: the rows above -level), g must be
// <= -level.
Tally probe(const Problem& p, const std::vector<const Constraint*>& cs, const ProximityScreen& screen, double spread,
            std::mt19937& rng, double level = 0.0) {
  const ProductLayout L(p);
  std::normal_distribution<double> jitter(0.0, spread);
  std::vector<char> near;
  std::vector<double> g(4);
  Tally t;
  for (int trial = 0; trial < 400; ++trial) {
    Eigen::VectorXd x(L.state_dim());
    for (size_t i = 0; i < p.agents.size(); ++i)
      for (int c = 0; c < 3; ++c) x[L.state[i] + c] = (c < 2 ? p.agents[i].x0[c] : 0.0) + jitter(rng) * (c < 2 ? 1 : 3);
    near = near_flags(screen, x.data(), cs.size(), nullptr, level);
    for (size_t i = 0; i < cs.size(); ++i) {
      if (near[i]) {
        ++t.near;
        continue;
      }
      ++t.skipped;
      cs[i]->evaluate(x.data(), g.data(), nullptr);
      for (int r = 0; r < cs[i]->size(); ++r)
        if (g[r] > -level) ++t.violated_skipped;
    }
  }
  return t;
}

// Each constraint of `cs` wrapped by `wrap` (a mutation of its reach, box or rate), kept alive
// beside the list a screen is built over.
struct Wrapped {
  std::vector<std::unique_ptr<Constraint>> owned;
  std::vector<const Constraint*> list;
};
template <class Wrap>
Wrapped wrapped(const std::vector<const Constraint*>& cs, Wrap wrap) {
  Wrapped w;
  for (const auto* c : cs) {
    w.owned.push_back(wrap(*c));
    w.list.push_back(w.owned.back().get());
  }
  return w;
}

std::vector<const Constraint*> pair_rows(const std::vector<std::shared_ptr<const Constraint>>& list) {
  std::vector<const Constraint*> cs;
  for (const auto& c : list)
    if (c->stage() == ConstraintStage::AllSteps) cs.push_back(c.get());
  return cs;
}

}  // namespace

TEST(ProximityScreen, LeavesOutOnlySatisfiedRows) {
  std::mt19937 rng(7);
  for (Norm norm : {Norm::Inf, Norm::Two})
    for (int rep = 0; rep < 3; ++rep) {
      const Problem p = team(14, 4.0, norm, rng);
      const auto pp = planning::assemble(p, p.horizon);
      for (const auto* list : {&pp.constraints, &pp.between}) {
        const auto cs = pair_rows(*list);
        const ProximityScreen screen(p, cs);
        ASSERT_TRUE(screen.active());
        const Tally t = probe(p, cs, screen, 0.4, rng);
        EXPECT_EQ(t.violated_skipped, 0) << "norm " << (norm == Norm::Inf ? "inf" : "2");
        EXPECT_GT(t.skipped, t.near / 4) << "the screen leaves out too little to matter";
      }
    }
}

TEST(ProximityScreen, AShrunkReachLetsViolatedRowsThrough) {
  std::mt19937 rng(11);
  for (Norm norm : {Norm::Inf, Norm::Two}) {
    const Problem p = team(14, 4.0, norm, rng);
    const auto pp = planning::assemble(p, p.horizon);
    const Wrapped shrunk = wrapped(pair_rows(pp.constraints), [](const Constraint& c) { return std::make_unique<ScaledReach>(c, 0.9); });
    const ProximityScreen screen(p, shrunk.list);
    EXPECT_GT(probe(p, shrunk.list, screen, 0.4, rng).violated_skipped, 0) << "norm " << (norm == Norm::Inf ? "inf" : "2");
  }
}

// The same constraint with its clear_outside box shrunk by 10% of its half-widths about its centre.
class ShrunkBox final : public Constraint {
 public:
  explicit ShrunkBox(const Constraint& c) : c_(c) {}
  std::string name() const override { return c_.name(); }
  int size() const override { return c_.size(); }
  ConstraintStage stage() const override { return c_.stage(); }
  const std::vector<int>& support() const override { return c_.support(); }
  void evaluate(const double* x, double* g, double* jac) const override { c_.evaluate(x, g, jac); }
  double pair_reach() const override { return c_.pair_reach(); }
  bool clear_outside(double lo[2], double hi[2]) const override {
    if (!c_.clear_outside(lo, hi)) return false;
    for (int k = 0; k < 2; ++k) {
      const double mid = 0.5 * (lo[k] + hi[k]), half = 0.5 * (hi[k] - lo[k]);
      lo[k] = mid - 0.9 * half;
      hi[k] = mid + 0.9 * half;
    }
    return true;
  }

 private:
  const Constraint& c_;
};

// A team among square and triangular obstacles placed where the agents start.
Problem team_among_obstacles(int N, double side, Norm norm, std::mt19937& rng) {
  Problem p = team(N, side, norm, rng);
  std::uniform_real_distribution<double> pos(0.0, side), size(0.2, 0.8);
  for (int o = 0; o < 8; ++o) {
    Obstacle ob;
    ob.name = "o" + std::to_string(o);
    const double cx = pos(rng), cy = pos(rng), r = size(rng);
    if (o % 2 == 0) {
      ob.vertices = {{cx - r, cy - r}, {cx + r, cy - r}, {cx + r, cy + r}, {cx - r, cy + r}};
      ob.is_box = true;
    } else {
      ob.vertices = {{cx - r, cy - r}, {cx + r, cy - 0.5 * r}, {cx, cy + r}};
    }
    p.obstacles.push_back(ob);
  }
  return p;
}

std::vector<const Constraint*> obstacle_rows(const std::vector<std::shared_ptr<const Constraint>>& list) {
  std::vector<const Constraint*> cs;
  for (const auto& c : list)
    if (c->stage() == ConstraintStage::AllSteps && c->name().rfind("obstacle", 0) == 0) cs.push_back(c.get());
  return cs;
}

// Obstacle rows are left out only where they hold (at the knots and, grown by the clearance
// between the samples, at the interior points), in both norms; and often enough to matter.
TEST(ProximityScreen, LeavesOutOnlySatisfiedObstacleRows) {
  std::mt19937 rng(5);
  for (Norm norm : {Norm::Inf, Norm::Two})
    for (int rep = 0; rep < 3; ++rep) {
      const Problem p = team_among_obstacles(10, 4.0, norm, rng);
      const auto pp = planning::assemble(p, p.horizon);
      for (const auto* list : {&pp.constraints, &pp.between}) {
        const auto cs = obstacle_rows(*list);
        ASSERT_EQ(cs.size(), 10u * 8u);
        const ProximityScreen screen(p, cs);
        ASSERT_TRUE(screen.active());
        const Tally t = probe(p, cs, screen, 0.4, rng);
        EXPECT_EQ(t.violated_skipped, 0) << "norm " << (norm == Norm::Inf ? "inf" : "2");
        EXPECT_GT(t.skipped, t.near) << "the screen leaves out too little to matter";
      }
    }
}

TEST(ProximityScreen, AShrunkObstacleBoxLetsViolatedRowsThrough) {
  std::mt19937 rng(13);
  long violated = 0;
  for (Norm norm : {Norm::Inf, Norm::Two}) {
    const Problem p = team_among_obstacles(10, 4.0, norm, rng);
    const auto pp = planning::assemble(p, p.horizon);
    const Wrapped shrunk = wrapped(obstacle_rows(pp.constraints), [](const Constraint& c) { return std::make_unique<ShrunkBox>(c); });
    const ProximityScreen screen(p, shrunk.list);
    violated += probe(p, shrunk.list, screen, 0.4, rng).violated_skipped;
  }
  EXPECT_GT(violated, 0);
}

TEST(ProximityScreen, FormationsAreNeverLeftOutFarObstaclesAre) {
  std::mt19937 rng(3);
  Problem p = team(6, 3.0, Norm::Inf, rng);
  Obstacle o;
  o.name = "box";
  o.vertices = {{1, 1}, {2, 1}, {2, 2}, {1, 2}};
  o.is_box = true;
  p.obstacles.push_back(o);
  p.formation.push_back({0, 1, 1.0, 0.5});
  const auto pp = planning::assemble(p, p.horizon);
  const auto cs = pair_rows(pp.constraints);
  const ProximityScreen screen(p, cs);
  std::vector<char> near;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(p.product_state_dim());
  for (int i = 0; i < 6; ++i) x[3 * i] = 100.0 * i;  // every pair far apart
  near = near_flags(screen, x.data(), cs.size());
  int pairs_left_out = 0, obstacles_left_out = 0;
  for (size_t i = 0; i < cs.size(); ++i) {
    const bool pair = cs[i]->name().rfind("collision", 0) == 0;
    const bool obstacle = cs[i]->name().rfind("obstacle", 0) == 0;
    if (!pair && !obstacle) EXPECT_TRUE(near[i]) << cs[i]->name();
    pairs_left_out += pair && !near[i];
    obstacles_left_out += obstacle && !near[i];
  }
  EXPECT_EQ(pairs_left_out, 6 * 5 / 2 - 0);  // the formation pair is a collision pair too
  // The box [1, 2]^2 grown by a margin under 0.3 and the clearance: all six agents, the nearest
  // at the origin, stand outside.
  EXPECT_EQ(obstacles_left_out, 6);
  // A disabled screen marks everything near.
  const ProximityScreen off(p, cs, false);
  near = near_flags(off, x.data(), cs.size());
  for (char c : near) EXPECT_TRUE(c);
}

// A solver's thread keeps its buffers from one knot to the next, and the agents' order along x
// starts from the last call's: over a walk in which agents overtake each other along x, the
// lists must be those of fresh buffers (a stale order would end the sweep early and drop pairs).
TEST(ProximityScreen, KeptBuffersGiveTheListsOfFreshOnes) {
  std::mt19937 rng(5);
  const Problem p = team(16, 3.0, Norm::Inf, rng);
  const auto pp = planning::assemble(p, p.horizon);
  const auto cs = pair_rows(pp.constraints);
  const ProximityScreen screen(p, cs);
  const ProductLayout L(p);
  Eigen::VectorXd x(L.state_dim());
  for (size_t i = 0; i < p.agents.size(); ++i) x.segment(L.state[i], 3) = p.agents[i].x0;
  std::normal_distribution<double> step(0.0, 0.3);
  ProximityScreen::Buffers kept;
  long near_pairs = 0;
  for (int k = 0; k < 200; ++k) {
    for (size_t i = 0; i < p.agents.size(); ++i) {
      x[L.state[i]] += step(rng);
      x[L.state[i] + 1] += step(rng);
    }
    ProximityScreen::Buffers fresh;
    const std::vector<char> a = near_flags(screen, x.data(), cs.size(), &kept);
    const std::vector<char> b = near_flags(screen, x.data(), cs.size(), &fresh);
    ASSERT_EQ(a, b) << "step " << k;
    for (char c : a) near_pairs += c;
  }
  EXPECT_GT(near_pairs, 200) << "the walk should keep some pairs within reach";
}

// With a level (the near-active rows a projection takes, polish.cpp): a row left out is at most
// -level, for pairs and obstacles, both norms, at the knots and between them; the lists still
// leave rows out; a decay rate 10 % too high lets near-active rows through, so this can fail.
TEST(ProximityScreen, WithALevelLeavesOutOnlyRowsBelowIt) {
  std::mt19937 rng(17);
  for (Norm norm : {Norm::Inf, Norm::Two})
    for (const double level : {1e-3, 0.05, 0.3}) {
      const Problem p = team_among_obstacles(12, 4.0, norm, rng);
      const auto pp = planning::assemble(p, p.horizon);
      for (const auto* list : {&pp.constraints, &pp.between}) {
        const auto cs = pair_rows(*list);
        const ProximityScreen screen(p, cs);
        const Tally t = probe(p, cs, screen, 0.4, rng, level);
        EXPECT_EQ(t.violated_skipped, 0) << "norm " << (norm == Norm::Inf ? "inf" : "2") << ", level " << level;
        EXPECT_GT(t.skipped, 0) << "level " << level;
      }
    }
  long through = 0;
  for (Norm norm : {Norm::Inf, Norm::Two}) {
    const Problem p = team_among_obstacles(12, 4.0, norm, rng);
    const auto pp = planning::assemble(p, p.horizon);
    const Wrapped fast = wrapped(pair_rows(pp.constraints), [](const Constraint& c) { return std::make_unique<ScaledReach>(c, 1.0, 1.1); });
    const ProximityScreen screen(p, fast.list);
    through += probe(p, fast.list, screen, 0.4, rng, 0.3).violated_skipped;
  }
  EXPECT_GT(through, 0);
}
