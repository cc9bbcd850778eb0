// Second derivatives of core's eps-robust constraints (what a second-order planner such as the
// ipopt plugin multiplies into its Lagrangian Hessian) against central differences of their
// exact Jacobians, on the examples' own constraints: obstacles and pairs in both norms,
// formations. A wrong entry anywhere shows up as a mismatch at some sample.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
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
  const auto lp = marsyn::load_problem(file.find('/') == std::string::npos
                                           ? std::string(MARSYN_SOURCE_DIR) + "/examples/" + file
                                           : file);
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

// examples/quadrotors.yaml (a 3-D workspace) with `norm` and, optionally, a formation pair and a
// slab bounded in z, written next to the test's scratch files.
std::string quadrotors_variant(const std::string& norm, bool formation) {
  std::ifstream in(std::string(MARSYN_SOURCE_DIR) + "/examples/quadrotors.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto at = text.find("delta_norm: inf");
  text.replace(at, std::string("delta_norm: inf").size(), "delta_norm: " + norm);
  const auto pillar = text.find("\n", text.find("{name: pillar"));
  text.insert(pillar + 1, "  - {name: slab, box: {lo: [0.4, -1.2, 1.9], hi: [0.9, -0.6, 2.2]}}\n");
  if (formation) text += "formation:\n  mu: 0.8\n  pairs:\n    - {agents: [north, south], lambda: 2.0}\n";
  const std::string path = (std::filesystem::temp_directory_path() / ("quadrotors_" + norm + ".yaml")).string();
  std::ofstream(path) << text;
  return path;
}

// The first derivatives of the 3-D constraints (prisms, pairs, formations in space) against
// central differences of g, away from kinks (where the one-sided differences disagree).
int check_jacobians(const std::string& file, int samples) {
  const auto lp = marsyn::load_problem(file);
  const auto& pb = lp.problem;
  EXPECT_EQ(pb.workspace_dim, 3);
  const auto pp = marsyn::planning::assemble(pb, pb.horizon);
  const int n = pb.product_state_dim();
  std::vector<double> lo, hi;
  for (const auto& a : pb.agents)
    for (int i = 0; i < a.n(); ++i) {
      lo.push_back(a.state_bounds.lo[i]);
      hi.push_back(a.state_bounds.hi[i]);
    }
  std::mt19937_64 rng(5);
  int checked = 0;
  for (const auto& c : pp.constraints) {
    if (c->name().rfind("obstacle", 0) && c->name().rfind("collision", 0) && c->name().rfind("formation", 0)) continue;
    const auto& sup = c->support();
    const int cols = static_cast<int>(sup.size()), rows = c->size();
    for (int s = 0; s < samples; ++s) {
      std::vector<double> x(n);
      for (int i = 0; i < n; ++i) x[i] = std::uniform_real_distribution<double>(lo[i], hi[i])(rng);
      std::vector<double> g(rows), J(rows * cols), gp(rows), gm(rows);
      c->evaluate(x.data(), g.data(), J.data());
      for (int j = 0; j < cols; ++j) {
        const double h = 1e-6;
        std::vector<double> xp = x, xm = x;
        xp[sup[j]] += h;
        xm[sup[j]] -= h;
        c->evaluate(xp.data(), gp.data(), nullptr);
        c->evaluate(xm.data(), gm.data(), nullptr);
        for (int r = 0; r < rows; ++r) {
          const double fwd = (gp[r] - g[r]) / h, bwd = (g[r] - gm[r]) / h;
          if (std::abs(fwd - bwd) > 1e-4) continue;  // a kink between the probes
          ++checked;
          EXPECT_NEAR(J[r * cols + j], (gp[r] - gm[r]) / (2 * h), 1e-5 * (1 + std::abs(J[r * cols + j])))
              << c->name() << " row " << r << " column " << j << " sample " << s;
          if (::testing::Test::HasFailure()) return checked;
        }
      }
    }
  }
  return checked;
}

TEST(ConstraintJacobian, ThreeDPrismsPairsAndFormationsInBothNorms) {
  for (const std::string norm : {"inf", "2"}) {
    SCOPED_TRACE(norm);
    EXPECT_GT(check_jacobians(quadrotors_variant(norm, norm == "2"), 30), 1000);
  }
}

TEST(ConstraintHessian, ThreeDEuclideanPairsAndFormations) {
  // Prisms and the inf-norm's nested smoothing decline (the planner differences them); the
  // Euclidean pair and the formation give their curvature in space.
  const auto counts = check_example(quadrotors_variant("2", true), 40);
  ASSERT_TRUE(counts.count("collision") && counts.count("formation"));
  EXPECT_GT(counts.at("collision").curved, 0);
  EXPECT_GT(counts.at("formation").curved, 0);
}

}  // namespace
