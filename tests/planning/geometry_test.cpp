#include <gtest/gtest.h>

#include "dynamics_cartpole/src/cartpole.hpp"
#include "marsyn/core/planning/geometry.hpp"
#include "marsyn/core/planning/margins.hpp"

using namespace marsyn;
using namespace marsyn::planning;

namespace {
Polygon unit_square() { return {{0, 0}, {1, 0}, {1, 1}, {0, 1}}; }
}  // namespace

TEST(Geometry, SignedDistanceOutsideInsideCorner) {
  const auto sq = unit_square();
  Eigen::Vector2d g;
  EXPECT_NEAR(signed_distance(sq, {2, 0.5}, &g), 1.0, 1e-12);
  EXPECT_NEAR(g.x(), 1.0, 1e-12);
  EXPECT_NEAR(signed_distance(sq, {0.5, 0.4}, &g), -0.4, 1e-12);
  EXPECT_NEAR(g.y(), -1.0, 1e-12);
  EXPECT_NEAR(signed_distance(sq, {2, 2}), std::sqrt(2.0), 1e-12);
}

TEST(Geometry, GrowByBoxIsTheInfNormNeighbourhood) {
  const auto grown = grow_by_box(unit_square(), 0.5, 0.25);
  ASSERT_EQ(grown.size(), 4u);
  // inf-distance to the square is 0.5 in x at (1.5, 0.5): exactly on the grown boundary.
  EXPECT_NEAR(signed_distance(grown, {1.5, 0.5}), 0.0, 1e-12);
  EXPECT_NEAR(signed_distance(grown, {0.5, 1.25}), 0.0, 1e-12);
  EXPECT_GT(signed_distance(grown, {1.51, 1.26}), 0.0);
  // A right triangle grows into a pentagon (the right-angle corner stays one vertex).
  EXPECT_EQ(grow_by_box({{0, 0}, {1, 0}, {0, 1}}, 0.1, 0.1).size(), 5u);
}

TEST(Margins, CraneTipMarginIsSoundAndNotWild) {
  auto crane = std::make_shared<models::CartPole>();
  AgentSpec a;
  a.name = "crane";
  a.dynamics = crane;
  a.x0 = Eigen::Vector4d(0, 0, M_PI, 0);
  a.tube.eps = Eigen::Vector4d(0.135, 0.385, 0.176, 0.768);
  a.workspace.footprint = 0;
  a.state_bounds = {Eigen::Vector4d(-0.195, -1.99, 1.20, -5.44), Eigen::Vector4d(5.49, 4.37, 4.68, 5.28)};
  const auto g = global_margin(a, a.state_bounds.shrunk(a.tube.eps));
  // |dp_x| <= eps_z + tip * eps_theta, and the cover adds only a little.
  EXPECT_GE(g.x, 0.135 + 0.5 * std::sin(0.176) - 1e-9);
  EXPECT_LE(g.x, 0.135 + 0.5 * 0.176 + 0.03);
  // Sampled states in the eps-box never move the tip further than the bounds.
  const MarginTable table(a, a.state_bounds.shrunk(a.tube.eps));
  std::srand(7);
  for (int trial = 0; trial < 2000; ++trial) {
    Eigen::Vector4d x;
    for (int i = 0; i < 4; ++i) {
      const double r = std::rand() / double(RAND_MAX);
      x[i] = a.state_bounds.lo[i] + a.tube.eps[i] + r * (a.state_bounds.hi[i] - a.state_bounds.lo[i] - 2 * a.tube.eps[i]);
    }
    const auto local = margin_at(a, x);
    EXPECT_LE(local.x, g.x + 1e-12);
    EXPECT_LE(local.y, g.y + 1e-12);
    const auto cell = table.at(x.data());
    EXPECT_LE(local.x, cell.x + 1e-12);
    EXPECT_LE(local.y, cell.y + 1e-12);
    Eigen::Vector4d y = x;
    for (int i = 0; i < 4; ++i) y[i] += a.tube.eps[i] * (2 * (std::rand() / double(RAND_MAX)) - 1);
    double px[2], py[2];
    crane->footprint_point(0, x.data(), px);
    crane->footprint_point(0, y.data(), py);
    EXPECT_LE(std::abs(px[0] - py[0]), local.x);
    EXPECT_LE(std::abs(px[1] - py[1]), local.y);
  }
}
