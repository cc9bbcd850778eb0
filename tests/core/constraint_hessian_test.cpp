// Second derivatives of core's eps-robust constraints (what a second-order planner such as the
// ipopt plugin multiplies into its Lagrangian Hessian) against central differences of their
// exact Jacobians, on the examples' own constraints: obstacles and pairs in both norms,
// formations. A wrong entry anywhere shows up as a mismatch at some sample.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "marsyn/core/planning/constraints.hpp"
#include "marsyn/core/problem/problem_loader.hpp"

namespace {

struct Counts {
  int checked = 0, curved = 0;
};

// Samples product states in the state bounds and checks every constraint that offers hessian().
std::map<std::string, Counts> check_example(const std::string& file, int samples) {
  const auto lp = marsyn::load_problem(std::string(MARSYN_SOURCE_DIR) + "/examples/" + file);
  const auto& pb = lp.problem;
  const auto pp = marsyn::planning::assemble(pb, pb.horizon);
  const int n = pb.product_state_dim();
  std::vector<double> lo, hi;
  for (const auto& a : pb.agents)
    for (int i = 0; i < a.n(); ++i) {
      lo.push_back(a.state_bounds.lo[i]);
      hi.push_back(a.state_bounds.hi[i]);
    }
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::map<std::string, Counts> counts;
  for (const auto& c : pp.constraints) {
    const auto& sup = c->support();
    const int cols = static_cast<int>(sup.size()), rows = c->size();
    const std::string kind = c->name().substr(0, c->name().find(' '));
    for (int s = 0; s < samples; ++s) {
      std::vector<double> x(n), w(rows);
      for (int i = 0; i < n; ++i) x[i] = std::uniform_real_distribution<double>(lo[i], hi[i])(rng);
      for (auto& v : w) v = unit(rng);
      std::vector<double> H(cols * cols, 0.0);
      if (!c->hessian(x.data(), w.data(), H.data())) break;
      ++counts[kind].checked;
      // Column j of the differenced Hessian: d/dx_j of sum_r w_r grad g_r.
      std::vector<double> Hd(cols * cols), jp(rows * cols), jm(rows * cols), gp(rows), gm(rows);
      for (int j = 0; j < cols; ++j) {
        const double h = 1e-6 * std::max(1.0, std::abs(x[sup[j]]));
        std::vector<double> xp = x, xm = x;
        xp[sup[j]] += h;
        xm[sup[j]] -= h;
        c->evaluate(xp.data(), gp.data(), jp.data());
        c->evaluate(xm.data(), gm.data(), jm.data());
        for (int q = 0; q < cols; ++q) {
          double v = 0.0;
          for (int r = 0; r < rows; ++r) v += w[r] * (jp[r * cols + q] - jm[r * cols + q]);
          Hd[q * cols + j] = v / (2 * h);
        }
      }
      double scale = 1.0;
      for (double v : H) scale = std::max(scale, std::abs(v));
      if (std::any_of(H.begin(), H.end(), [](double v) { return v != 0.0; })) ++counts[kind].curved;
      for (int p = 0; p < cols; ++p)
        for (int q = 0; q < cols; ++q)
          EXPECT_NEAR(H[p * cols + q], Hd[p * cols + q], 1e-6 * scale)
              << file << ": " << c->name() << " entry (" << p << ", " << q << ") sample " << s;
      if (::testing::Test::HasFailure()) return counts;
    }
  }
  return counts;
}

TEST(ConstraintHessian, InfNormPairsAndBoxObstacles) {
  const auto counts = check_example("multi_drone.yaml", 40);
  ASSERT_TRUE(counts.count("obstacle") && counts.count("collision"));
  EXPECT_GT(counts.at("obstacle").curved, 0);   // a sample in a grown corner's vertex region
  EXPECT_GT(counts.at("collision").curved, 0);  // a sample in the smoothed corner of the max
}

TEST(ConstraintHessian, EuclideanPairsAndPolygonObstacles) {
  const auto counts = check_example("lane_merging.yaml", 60);
  ASSERT_TRUE(counts.count("obstacle") && counts.count("collision"));
  EXPECT_GT(counts.at("obstacle").curved, 0);
  EXPECT_GT(counts.at("collision").curved, 0);
}

TEST(ConstraintHessian, Formation) {
  const auto counts = check_example("formation.yaml", 40);
  ASSERT_TRUE(counts.count("formation"));
  EXPECT_EQ(counts.at("formation").curved, counts.at("formation").checked);
}

TEST(ConstraintHessian, NonlinearFootprintCurvature) {
  // The crane's pendulum tip: the pair constraint adds the footprint's own second derivative.
  const auto counts = check_example("crane_vehicle.yaml", 200);
  ASSERT_TRUE(counts.count("collision"));
  EXPECT_EQ(counts.at("collision").checked, 200);
  EXPECT_GT(counts.at("collision").curved, 0);
}

}  // namespace
