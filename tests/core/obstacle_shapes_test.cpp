// A round obstacle (`circle: {center, radius}`) enters every stage as the regular polygon around
// the disk: sound only if no point of the disk lies outside the polygon, rounding included.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "marsyn/core/problem/problem_loader.hpp"

namespace {

std::string with_obstacle(const std::string& name, const std::string& obstacle) {
  const std::string path = testing::TempDir() + "/" + name + ".yaml";
  std::ofstream(path) << "tau: 0.1\nhorizon: 40\n"
                         "agents:\n"
                         "  - {name: r, dynamics: unicycle, x0: [0, 0, 0], goal: {center: [2, 0, 0], radius: [0.3, 0.3, 0.5]},\n"
                         "     state_bounds: {lo: [-1, -1, -4], hi: [3, 1, 4]}, input_bounds: {lo: [-1, -1], hi: [1, 1]},\n"
                         "     disturbance: [0, 0, 0], eps: [0.05, 0.05, 0.1], workspace: {position: [0, 1]}}\n"
                         "obstacles:\n  - "
                      << obstacle << "\n";
  return path;
}

// The disk's every point is inside (or on) every edge's inner side: each edge line's distance from
// the centre, computed in long double, is at least the radius.
void expect_polygon_holds_disk(const std::vector<Eigen::Vector2d>& v, Eigen::Vector2d c, double r) {
  ASSERT_GE(v.size(), 8u);
  for (std::size_t i = 0; i < v.size(); ++i) {
    const auto& a = v[i];
    const auto& b = v[(i + 1) % v.size()];
    const long double ex = (long double)b.x() - a.x(), ey = (long double)b.y() - a.y();
    // Counter-clockwise: the centre lies left of every edge, at distance cross(e, c - a) / |e|.
    const long double d = (ex * ((long double)c.y() - a.y()) - ey * ((long double)c.x() - a.x())) / std::sqrt(ex * ex + ey * ey);
    EXPECT_GE(d, (long double)r) << "edge " << i << " cuts the disk";
    EXPECT_LE((double)d, 1.0001 * r) << "edge " << i << " far from the disk";
  }
  for (const auto& p : v) EXPECT_LE((p - c).norm(), 1.02 * r);  // at most 2 % wider, at the corners
}

TEST(ObstacleShapes, ACircleIsThePolygonAroundTheDisk) {
  for (const auto& [c, r] : std::vector<std::pair<Eigen::Vector2d, double>>{
           {{5, 5}, 0.6}, {{-1234.5, 987.25}, 0.01}, {{20.1, -30.3}, 7.0}, {{1e4, 1e4}, 1e-3}}) {
    std::ostringstream ob;
    ob.precision(17);
    ob << "{name: post, circle: {center: [" << c.x() << ", " << c.y() << "], radius: " << r << "}}";
    const auto lp = marsyn::load_problem(with_obstacle("circle", ob.str()));
    ASSERT_EQ(lp.problem.obstacles.size(), 1u);
    EXPECT_FALSE(lp.problem.obstacles[0].is_box);
    expect_polygon_holds_disk(lp.problem.obstacles[0].vertices, c, r);
  }
}

}  // namespace
