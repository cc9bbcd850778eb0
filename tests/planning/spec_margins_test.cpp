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

Point lift(const V& v) { return {v.x(), v.y(), 0.0}; }

// Points of the box p + [-m.x, m.x] x [-m.y, m.y] x [-m.z, m.z] on a grid.
std::vector<Point> box_points3(const Point& p, const WorkspaceMargin& m, int k = 8) {
  std::vector<Point> out;
  for (int i = 0; i <= k; ++i)
    for (int j = 0; j <= k; ++j)
      for (int l = 0; l <= k; ++l)
        out.emplace_back(p.x() - m.x + 2 * m.x * i / k, p.y() - m.y + 2 * m.y * j / k, p.z() - m.z + 2 * m.z * l / k);
  return out;
}

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
  EXPECT_DOUBLE_EQ(collision_margin({0, 0, 0}, {}, {3, -1, 0}, {}, 0.5, Norm::Inf), 2.5);
  EXPECT_DOUBLE_EQ(collision_margin({0, 0, 0}, {}, {3, 4, 0}, {}, 0.5, Norm::Two), 4.5);
  EXPECT_DOUBLE_EQ(formation_margin({0, 0, 0}, {}, {3, 4, 0}, {}, 5.5, 1.0), 0.5);
  EXPECT_DOUBLE_EQ(formation_margin({0, 0, 0}, {}, {3, 4, 0}, {}, 3.5, 1.0), -0.5);
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
      const double pair = collision_margin(lift(p), mp, lift(q), mq, 0.4, norm);
      const double form = formation_margin(lift(p), mp, lift(q), mq, 2.0, 1.2);
      double worst_pair = 1e300, worst_form = 1e300;
      for (const V& a : box_points(p, mp, 6))
        for (const V& b : box_points(q, mq, 6)) {
          worst_pair = std::min(worst_pair, collision_margin(lift(a), {}, lift(b), {}, 0.4, norm));
          worst_form = std::min(worst_form, formation_margin(lift(a), {}, lift(b), {}, 2.0, 1.2));
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

// Prisms in space: the exact distance against points sampled on the prism's surface (brute
// force), and the margin box's verdict at every point of the box.
TEST(SpecMargins, PrismDistanceIsTheBruteForceOneAndTheBoxVerdictHolds) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> pos(-4, 4), half(0.0, 0.5), zc(-1, 1), zh(0.2, 1.0);
  int decided = 0, outside = 0;
  for (const Norm norm : {Norm::Inf, Norm::Two})
    for (int t = 0; t < 300; ++t) {
      Obstacle o;
      o.vertices = random_polygon(rng);
      if (o.vertices.size() < 3) continue;
      const double c = zc(rng), h = zh(rng);
      o.z_lo = c - h;
      o.z_hi = c + h;
      const Point p(pos(rng), pos(rng), 2 * zc(rng));
      // Exact: the distance to the prism (outside) is min over its surface; sample the side walls
      // and both caps finely.
      const double exact = obstacle_margin(o, p, {}, 0.0, norm);
      if (exact > 0) {
        ++outside;
        double brute = 1e300;
        const auto& P = o.vertices;
        auto dist = [&](const Point& q) { return norm == Norm::Inf ? (q - p).lpNorm<Eigen::Infinity>() : (q - p).norm(); };
        for (std::size_t e = 0; e < P.size(); ++e)
          for (int i = 0; i <= 40; ++i)
            for (int j = 0; j <= 40; ++j) {
              const V xy = P[e] + (P[(e + 1) % P.size()] - P[e]) * (i / 40.0);
              brute = std::min(brute, dist(Point(xy.x(), xy.y(), o.z_lo + (o.z_hi - o.z_lo) * j / 40.0)));
            }
        // The caps: the nearest cap point is p's x-y clamped into the polygon (its nearest point).
        for (const double zc2 : {o.z_lo, o.z_hi}) {
          const V xy(p.x(), p.y());
          if (signed_distance_two(P, xy) <= 0) brute = std::min(brute, dist(Point(p.x(), p.y(), zc2)));
        }
        EXPECT_LE(exact, brute + 1e-12) << "never above the distance to a surface point";
        EXPECT_NEAR(exact, brute, 0.12) << "and near the sampled minimum";
      }
      const WorkspaceMargin m{half(rng), half(rng), half(rng)};
      const double robust = obstacle_margin(o, p, m, 0.3, norm);
      double worst = 1e300;
      for (const Point& q : box_points3(p, m)) worst = std::min(worst, obstacle_margin(o, q, {}, 0.3, norm));
      if (robust >= 0) {
        ++decided;
        EXPECT_GE(worst, -1e-12) << "sound: every point of the box keeps delta";
      }
      if (robust >= 0 || worst > 0) EXPECT_NEAR(robust, worst, 0.15);
    }
  EXPECT_GT(decided, 100);
  EXPECT_GT(outside, 100);
}

TEST(SpecMargins, ThreeDPairsAndFormationsHoldForEveryPairOfPoints) {
  std::mt19937_64 rng(22);
  std::uniform_real_distribution<double> pos(-2, 2), half(0.0, 0.3), u(-1, 1), scale(0.6, 1.4);
  int decided_pair = 0, decided_formation = 0;
  for (const Norm norm : {Norm::Inf, Norm::Two})
    for (int t = 0; t < 400; ++t) {
      const WorkspaceMargin mp{half(rng), half(rng), half(rng)}, mq{half(rng), half(rng), half(rng)};
      const double reach = t % 2 ? 0.4 + mp.two() + mq.two() : 2.0, r = scale(rng) * reach;
      const Point dir = Point(u(rng), u(rng), u(rng)).normalized();
      const Point p(pos(rng), pos(rng), pos(rng)), q = p + r * dir;
      const double pair = collision_margin(p, mp, q, mq, 0.4, norm);
      const double form = formation_margin(p, mp, q, mq, 2.0, 1.2);
      double worst_pair = 1e300, worst_form = 1e300;
      for (const Point& a : box_points3(p, mp, 3))
        for (const Point& b : box_points3(q, mq, 3)) {
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
  EXPECT_GT(decided_pair, 60);
  EXPECT_GT(decided_formation, 30);
}

TEST(SpecMargins, APairApartInXYCollidesInZ) {
  // Same x-y, 0.1 apart in height: in the plane they would coincide; in space they collide
  // (delta 0.25) in both norms; 1 m apart in height they are clear.
  for (const Norm norm : {Norm::Inf, Norm::Two}) {
    EXPECT_DOUBLE_EQ(collision_margin({1, 2, 0.0}, {}, {1, 2, 0.1}, {}, 0.25, norm), 0.1 - 0.25);
    EXPECT_DOUBLE_EQ(collision_margin({1, 2, 0.0}, {}, {1, 2, 1.0}, {}, 0.25, norm), 1.0 - 0.25);
    // Apart in x-y by 1, but the z margins (0.3 each) do not change an x-y clearance.
    EXPECT_DOUBLE_EQ(collision_margin({0, 0, 0}, {0, 0, 0.3}, {1, 0, 0}, {0, 0, 0.3}, 0.25, Norm::Inf), 0.75);
  }
  // A slab over the floor at heights [1, 2]: under it (z = 0.5) 0.5 away, inside it -0.3 deep.
  Obstacle slab;
  slab.vertices = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
  slab.z_lo = 1;
  slab.z_hi = 2;
  EXPECT_DOUBLE_EQ(obstacle_margin(slab, {2, 2, 0.5}, {}, 0.0, Norm::Two), 0.5);
  EXPECT_DOUBLE_EQ(obstacle_margin(slab, {2, 2, 1.3}, {}, 0.0, Norm::Inf), -0.3);
  // Beyond an edge and below: hypot in the 2-norm, the max in the inf-norm.
  EXPECT_DOUBLE_EQ(obstacle_margin(slab, {5, 2, 0.0}, {}, 0.0, Norm::Two), std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(obstacle_margin(slab, {5, 2, 0.0}, {}, 0.0, Norm::Inf), 1.0);
  // In the plane's form (z unbounded) the prism is the polygon: the 2-D value bit for bit.
  Obstacle column;
  column.vertices = slab.vertices;
  EXPECT_EQ(obstacle_margin(column, {5.3, 2.7, 123.0}, {0.1, 0.2, 0.0}, 0.25, Norm::Two),
            obstacle_margin(column.vertices, V(5.3, 2.7), {0.1, 0.2, 0.0}, 0.25, Norm::Two));
}
