// The funnel on a linear system, where the exact reachable set is known: a double integrator
// (p' = v, v' = a + w) tracking a nominal with inputs well inside U, so the closed loop of the
// deviation e = x - x_k is exactly e_{k+1} = (Phi + Gamma K_k) e_k + int_0^tau e^{A (tau - s)} w(s) ds.
// Its reachable set's extent along each coordinate (support function) is computed here by
// quadrature, and compared with the enclosure the verification carried (Z_k): Z_k must contain it
// at every step (soundness: a shrunk disturbance term fails this), and the median ratio is the
// tightness figure of docs/funnel.md on a case with no sampling in the denominator.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "dynamics_double_integrator/src/double_integrator.hpp"
#include "funnel_scenarios.hpp"
#include "funnel_tracker.hpp"

namespace marsyn::funnel {
namespace {

using testing::vec;

TrackingProblem double_integrator(int steps) {
  TrackingProblem p;
  p.agent = "cart";
  p.dynamics = std::make_shared<models::DoubleIntegrator>();
  p.tube.eps = vec({0.2, 0.3});
  p.tube.w = vec({0.0, 0.1});
  p.input_bounds = {vec({-20.0}), vec({20.0})};
  p.state_bounds = {vec({-10, -10}), vec({20, 10})};
  p.nominal = testing::simulate(*p.dynamics, vec({0, 0}), steps, p.tau, [](double t) { return vec({std::sin(t)}); });
  return p;
}

// max over the reachable deviations at each step of |e_i|, exactly (up to the quadrature):
// the initial box's image plus, for every earlier period j, the support of that period's
// disturbance integral mapped by the closed loop from j + 1 to k.
std::vector<Eigen::Vector2d> exact_extent(const FunnelData& d, const Eigen::Vector2d& r0, double tau, double wv) {
  const int T = d.horizon();
  Eigen::Matrix2d Phi;
  Phi << 1, tau, 0, 1;
  const Eigen::Vector2d Gamma(tau * tau / 2, tau);
  std::vector<Eigen::Matrix2d> Acl(T);
  for (int k = 0; k < T; ++k) Acl[k] = Phi + Gamma * Eigen::RowVector2d(d.K[k][0], d.K[k][1]);
  // Support of int_0^tau e^{A (tau - s)} (0, w(s)) ds, |w| <= wv, in direction c:
  // int_0^tau |c0 (tau - s) + c1| wv ds (Simpson on a fine grid; the kink is resolved well enough).
  auto disturbance_support = [&](const Eigen::Vector2d& c) {
    constexpr int kPieces = 4000;
    const double h = tau / kPieces;
    double sum = 0;
    for (int q = 0; q <= kPieces; ++q) {
      const double s = q * h, f = std::fabs(c[0] * (tau - s) + c[1]) * wv;
      sum += f * (q == 0 || q == kPieces ? 1 : (q % 2 ? 4 : 2));
    }
    return sum * h / 3;
  };
  std::vector<Eigen::Vector2d> out(T + 1);
  for (int k = 0; k <= T; ++k) {
    for (int i = 0; i < 2; ++i) {
      // c^T M_{k,j} for j = k, k - 1, ..., 0 (M_{k,k} = I).
      Eigen::RowVector2d row = Eigen::RowVector2d::Zero();
      row[i] = 1;
      double extent = 0;
      for (int j = k - 1; j >= 0; --j) {
        extent += disturbance_support(row.transpose());  // period j's disturbance, seen at k
        row = row * Acl[j];
      }
      extent += std::fabs(row[0]) * r0[0] + std::fabs(row[1]) * r0[1];  // the initial box
      out[k][i] = extent;
    }
  }
  return out;
}

TEST(FunnelLinear, TheCarriedEnclosureContainsTheExactReachableSetAndIsTight) {
  const TrackingProblem p = double_integrator(60);
  // One pass each: order 8 (the cheap pass), and order 24 forced by max_generators (24 n + n + m).
  for (const char* reach : {"8", "24"}) {
    Params params;
    params.set("reach_order", std::stol(reach));
    params.set("max_generators", std::stol(reach) * 2 + 3);
    FunnelTracker tracker(params);
    std::vector<std::vector<Zonotope>> reach_sets;  // per step, the carried set's parts
    tracker.keep_reach_sets_for_tests(&reach_sets);
    const TrackResult r = tracker.track(p, {});
    ASSERT_EQ(r.status, TrackerStatus::ControllerFound) << r.message;
    EXPECT_EQ(r.message.find("saturate"), std::string::npos) << "the inputs must stay inside U: " << r.message;
    const FunnelData& d = dynamic_cast<const FunnelController&>(*r.controller).data();
    const Eigen::Vector2d r0 = 0.1 * p.tube.eps;  // the default initial box
    const auto exact = exact_extent(d, r0, p.tau, p.tube.w[1]);
    ASSERT_EQ(reach_sets.size(), exact.size());
    std::vector<double> ratios;
    for (std::size_t k = 1; k < exact.size(); ++k)
      for (int i = 0; i < 2; ++i) {
        double verified = 0.0;
        for (const Zonotope& z : reach_sets[k]) {
          const FastInterval h = z.hull(i);
          const double xk = p.nominal.x[k][i];
          verified = std::max(verified, std::max(h.upper() - xk, xk - h.lower()));
        }
        EXPECT_GE(verified, exact[k][i] * (1 - 1e-6)) << "step " << k << ", coordinate " << i;
        ratios.push_back(verified / exact[k][i]);
      }
    std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
    const double median = ratios[ratios.size() / 2];
    std::printf("double integrator, carried with %s n generators: tightness median %.3fx, max %.3fx\n", reach, median,
                *std::max_element(ratios.begin(), ratios.end()));
    EXPECT_LE(median, 1.3) << "reach_order " << reach;
  }
}

}  // namespace
}  // namespace marsyn::funnel
