// The one evaluator's formulas against brute force: a margin box's verdict must hold at every
// point of the box (soundness), and must not be far from the worst point (tightness). Scaling the
// margin box down by 10% inside obstacle_margin / collision_margin / formation_margin makes the
// soundness checks fail.
#include <gtest/gtest.h>

#include <random>

#include "marsyn/core/planning/spec_margins.hpp"

using namespace marsyn;
using namespace marsyn::planning;
using V = Eigen::Vector2d;

namespace {

// Points of the box p + [-m.x, m.x] x [-m.y, m.y] on a grid, corners and edges included.
std::vector<V> box_points(const V& p, const WorkspaceMargin& m, int k = 24) {
  std::vector<V> out;
  for (int i = 0; i <= k; ++i)
    for (int j = 0; j <= k; ++j) out.emplace_back(p.x() - m.x + 2 * m.x * i / k, p.y() - m.y + 2 * m.y * j / k);
  return out;
}

Polygon random_polygon(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> c(-2, 2), r(0.2, 1.5);
  const V centre(c(rng), c(rng));
  std::vector<V> pts;
  for (int i = 0; i < 7; ++i) pts.push_back(centre + V(r(rng) * (c(rng) / 2), r(rng) * (c(rng) / 2)));
  return convex_hull(pts);
}

}  // namespace

TEST(SpecMargins, ObstacleVerdictHoldsAtEveryPointOfTheMarginBoxAndIsTight) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> pos(-4, 4), half(0.0, 0.6);
  int decided = 0;
  for (const Norm norm : {Norm::Inf, Norm::Two})
    for (int t = 0; t < 400; ++t) {
      const Polygon P = random_polygon(rng);
      if (P.size() < 3) continue;
      const V p(pos(rng), pos(rng));
      const WorkspaceMargin m{half(rng), half(rng)};
      const double delta = 0.3;
      const double robust = obstacle_margin(P, p, m, delta, norm);
      double worst = 1e300;
      for (const V& q : box_points(p, m)) worst = std::min(worst, obstacle_margin(P, q, {}, delta, norm));
      if (robust >= 0) {
        ++decided;
        EXPECT_GE(worst, -1e-12) << "sound: every point of the box keeps delta";
      }
      // Tight: the margin of the box is the worst point's, up to the grid's resolution.
      if (robust >= 0 || worst > 0) EXPECT_NEAR(robust, worst, 0.08) << (norm == Norm::Inf ? "inf" : "two");
    }
  EXPECT_GT(decided, 100);
}

TEST(SpecMargins, WithoutAMarginBoxItIsTheRealSpecification) {
  const Polygon sq{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  EXPECT_DOUBLE_EQ(obstacle_margin(sq, {2.0, 2.5}, {}, 0.25, Norm::Inf), 1.5 - 0.25);
  EXPECT_DOUBLE_EQ(obstacle_margin(sq, {2.0, 2.5}, {}, 0.25, Norm::Two), std::sqrt(1.0 + 2.25) - 0.25);
  EXPECT_DOUBLE_EQ(obstacle_margin(sq, {0.5, 0.4}, {}, 0.0, Norm::Inf), -0.4);  // inside: depth
  EXPECT_DOUBLE_EQ(collision_margin({0, 0}, {}, {3, -1}, {}, 0.5, Norm::Inf), 2.5);
  EXPECT_DOUBLE_EQ(collision_margin({0, 0}, {}, {3, 4}, {}, 0.5, Norm::Two), 4.5);
  EXPECT_DOUBLE_EQ(formation_margin({0, 0}, {}, {3, 4}, {}, 5.5, 1.0), 0.5);
  EXPECT_DOUBLE_EQ(formation_margin({0, 0}, {}, {3, 4}, {}, 3.5, 1.0), -0.5);
}

TEST(SpecMargins, PairAndFormationVerdictsHoldForEveryPairOfPoints) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> pos(-2, 2), half(0.0, 0.4), angle(0, 6.3), scale(0.6, 1.4);
  int decided_pair = 0, decided_formation = 0;
  for (const Norm norm : {Norm::Inf, Norm::Two})
    for (int t = 0; t < 600; ++t) {
      const WorkspaceMargin mp{half(rng), half(rng)}, mq{half(rng), half(rng)};
      // q near the boundary of either verdict: about delta + the margins away, or about lambda.
      const double reach = t % 2 ? 0.4 + mp.two() + mq.two() : 2.0, a = angle(rng), r = scale(rng) * reach;
      const V p(pos(rng), pos(rng)), q = p + r * V(std::cos(a), std::sin(a));
      const double pair = collision_margin(p, mp, q, mq, 0.4, norm);
      const double form = formation_margin(p, mp, q, mq, 2.0, 1.2);
      double worst_pair = 1e300, worst_form = 1e300;
      for (const V& a : box_points(p, mp, 6))
        for (const V& b : box_points(q, mq, 6)) {
          worst_pair = std::min(worst_pair, collision_margin(a, {}, b, {}, 0.4, norm));
          worst_form = std::min(worst_form, formation_margin(a, {}, b, {}, 2.0, 1.2));
        }
      if (pair >= 0) {
        ++decided_pair;
        EXPECT_GE(worst_pair, -1e-12);
      }
      if (form >= 0) {
        ++decided_formation;
        EXPECT_GE(worst_form, -1e-12);
      }
    }
  EXPECT_GT(decided_pair, 100);
  EXPECT_GT(decided_formation, 50);
}

TEST(SpecMargins, EveryRequirementOnceInOneOrder) {
  Problem pb;
  for (int i = 0; i < 3; ++i) {
    AgentSpec a;
    a.name = "a" + std::to_string(i);
    pb.agents.push_back(a);
  }
  pb.obstacles.resize(2);
  pb.obstacles[0].name = "wall";
  pb.obstacles[1].name = "post";
  pb.formation.push_back({2, 0, 1.0, 0.1});
  std::vector<std::string> names;
  for_each_requirement(pb, [&](const Requirement& r) { names.push_back(r.name(pb)); });
  const std::vector<std::string> want{"obstacle wall vs a0", "obstacle post vs a0", "obstacle wall vs a1",
                                      "obstacle post vs a1", "obstacle wall vs a2", "obstacle post vs a2",
                                      "collision a0 vs a1", "collision a0 vs a2", "collision a1 vs a2",
                                      "formation a2 - a0"};
  EXPECT_EQ(names, want);
  pb.pairwise_collision = false;
  names.clear();
  for_each_requirement(pb, [&](const Requirement& r) { names.push_back(r.name(pb)); });
  EXPECT_EQ(names.size(), 7u);
}
