#include <gtest/gtest.h>

#include <cmath>
#include <random>

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

namespace {

// A rig's middle 1.5 m behind the axle, (x - 1.5 cos(theta - beta), y - 1.5 sin(theta - beta)):
// a footprint reading four of the five states.
class Hitch : public DynamicsModel<Hitch> {
 public:
  std::string type() const override { return "hitch"; }
  int state_dim() const override { return 5; }
  int input_dim() const override { return 2; }
  std::vector<std::string> state_names() const override { return {"x", "y", "theta", "beta", "s"}; }
  std::vector<std::string> input_names() const override { return {"v", "omega"}; }
  std::vector<std::string> footprints() const override { return {"rig_middle"}; }
  template <class S>
  void vector_field(const S* x, const S* u, S* dx) const {
    using std::cos, std::sin;
    dx[0] = x[4] * cos(x[2]);
    dx[1] = x[4] * sin(x[2]);
    dx[2] = u[1];
    dx[3] = u[1] - x[4] / 3.0 * sin(x[3]);
    dx[4] = (u[0] - x[4]) / 0.8;
  }
  template <class S>
  void footprint_point(int, const S* x, S* p) const {
    using std::cos, std::sin;
    p[0] = x[0] - 1.5 * cos(x[2] - x[3]);
    p[1] = x[1] - 1.5 * sin(x[2] - x[3]);
  }
};

}  // namespace

// Four coordinates read: no table (8 cells per coordinate made the margin 7.5 m on a 40 m apron),
// the bound at the state itself, sound on samples and within 10 % of the true reach.
TEST(Margins, AFootprintReadingFourCoordinatesIsBoundedAtTheState) {
  auto hitch = std::make_shared<Hitch>();
  AgentSpec a;
  a.name = "rig";
  a.dynamics = hitch;
  a.x0 = (Eigen::VectorXd(5) << 30, 4, 1.5708, 0, 0).finished();
  a.goal = {(Eigen::VectorXd(5) << 29, 19, 1, -0.3, -0.5).finished(), (Eigen::VectorXd(5) << 31, 21, 2, 0.3, 0.5).finished()};
  a.tube.eps = (Eigen::VectorXd(5) << 0.2, 0.2, 0.05, 0.05, 0.1).finished();
  a.workspace.footprint = 0;
  a.state_bounds = {(Eigen::VectorXd(5) << 0, 0, -4, -1.2, -1).finished(), (Eigen::VectorXd(5) << 40, 24, 4, 1.2, 3).finished()};
  const MarginTable table(a, a.state_bounds.shrunk(a.tube.eps));
  // The true reach over every state: 0.2 + 1.5 x 2 sin(0.05) in each coordinate.
  const double reach = 0.2 + 3.0 * std::sin(0.05);
  const auto g = table.max();
  EXPECT_GT(std::max(g.x, g.y), 0.9 * reach);
  EXPECT_LT(std::max(g.x, g.y), 1.1 * reach);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst_share = 0.0;  // the largest sampled deviation over the bound, per coordinate
  for (int trial = 0; trial < 4000; ++trial) {
    Eigen::VectorXd x(5), y(5);
    for (int i = 0; i < 5; ++i)
      x[i] = a.state_bounds.lo[i] + a.tube.eps[i] + unit(rng) * (a.state_bounds.hi[i] - a.state_bounds.lo[i] - 2 * a.tube.eps[i]);
    const auto at = table.at(x.data());
    const auto local = margin_at(a, x);
    EXPECT_EQ(at.x, local.x);
    EXPECT_EQ(at.y, local.y);
    for (int i = 0; i < 5; ++i) y[i] = x[i] + a.tube.eps[i] * (unit(rng) < 0.5 ? -1.0 : 1.0) * (0.9 + 0.1 * unit(rng));
    double px[2], py[2];
    hitch->footprint_point(0, x.data(), px);
    hitch->footprint_point(0, y.data(), py);
    EXPECT_LE(std::abs(px[0] - py[0]), at.x);
    EXPECT_LE(std::abs(px[1] - py[1]), at.y);
    worst_share = std::max({worst_share, std::abs(px[0] - py[0]) / at.x, std::abs(px[1] - py[1]) / at.y});
  }
  // Tight: a bound 10 % smaller would be broken by the samples.
  EXPECT_GT(worst_share, 0.9);
}
