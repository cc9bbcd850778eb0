#include "tightness.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <random>
#include <sstream>

#include <Eigen/Dense>

#include "marsyn/sampled_map.hpp"

namespace marsyn::funnel {
namespace {

double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// w pushes x away from the nominal interpolated linearly over period k (fine step q of `fine`).
void push_away(const FunnelData& d, int k, int q, int fine, const std::vector<double>& x, std::vector<double>& w) {
  const double s = static_cast<double>(q) / fine;
  for (int i = 0; i < d.n; ++i) {
    const double ref = (1 - s) * d.x_nom[k][i] + s * d.x_nom[k + 1][i];
    w[i] = x[i] >= ref ? d.w[i] : -d.w[i];
  }
}

// The closed loop's period map about the nominal, x_{k+1} = F_k(x_k, w) with the input held and
// w constant over the period, by central differences: Phi_k = dF/dx, G_k = dF/dw.
struct PeriodJacobians {
  std::vector<Eigen::MatrixXd> phi, g;
};

std::optional<PeriodJacobians> period_jacobians(const Dynamics& f, const FunnelController& ctrl, int fine) {
  const FunnelData& d = ctrl.data();
  const int n = d.n, m = d.m, T = d.horizon();
  std::vector<double> u(m), y(n), next(n), w(n);
  auto map = [&](std::vector<double> x, int k, const std::vector<double>& wk, Eigen::VectorXd& out) {
    if (ctrl.input(x.data(), k, u.data()) != ControlStatus::Ok) return false;
    for (int q = 0; q < fine; ++q) {
      rk4_step<double>(f, x.data(), u.data(), wk.data(), d.tau / fine, 1, next.data());
      x = next;
    }
    out = Eigen::Map<const Eigen::VectorXd>(x.data(), n);
    return true;
  };
  PeriodJacobians J;
  Eigen::VectorXd plus, minus;
  const std::vector<double> zero(n, 0.0);
  for (int k = 0; k < T; ++k) {
    Eigen::MatrixXd phi(n, n), g(n, n);
    for (int j = 0; j < n; ++j) {
      std::vector<double> xp = d.x_nom[k], xm = d.x_nom[k];
      const double h = 1e-6 * (1.0 + std::fabs(d.x_nom[k][j]));
      xp[j] += h;
      xm[j] -= h;
      if (!map(xp, k, zero, plus) || !map(xm, k, zero, minus)) return std::nullopt;
      phi.col(j) = (plus - minus) / (2 * h);
      std::vector<double> wp = zero, wm = zero;
      wp[j] = 1e-6;
      wm[j] = -1e-6;
      if (!map(d.x_nom[k], k, wp, plus) || !map(d.x_nom[k], k, wm, minus)) return std::nullopt;
      g.col(j) = (plus - minus) / 2e-6;
    }
    J.phi.push_back(std::move(phi));
    J.g.push_back(std::move(g));
  }
  return J;
}

// The linearized closed loop's worst case for coordinate i at step K, either sign: the costate
// lambda_K = +-e_i propagated back (lambda_j = Phi_j' lambda_{j+1}) picks the vertex of [-W, W]
// for every period (sign of G_j' lambda_{j+1}) and of the initial box (sign of lambda_0); after K
// the run pushes away from the nominal. Exact for a linear system; a strong guess near one
// (random vertices rarely line up over many periods).
void linearized_worst_cases(const Dynamics& f, const FunnelController& ctrl, int fine,
                            const std::function<void(const std::function<void(int, int)>&)>& run,
                            std::vector<double>& x, std::vector<double>& w) {
  const FunnelData& d = ctrl.data();
  const int n = d.n, T = d.horizon();
  const auto J = period_jacobians(f, ctrl, fine);
  if (!J || T < 1) return;
  std::vector<int> targets;
  for (int q = 1; q <= 4; ++q) targets.push_back(std::max(1, static_cast<int>(std::lround(T * q / 4.0))));
  targets.erase(std::unique(targets.begin(), targets.end()), targets.end());
  std::vector<std::vector<double>> plan(T, std::vector<double>(n));
  for (int K : targets)
    for (int i = 0; i < n; ++i)
      for (double sign : {1.0, -1.0}) {
        Eigen::VectorXd lambda = Eigen::VectorXd::Unit(n, i) * sign;
        for (int j = K - 1; j >= 0; --j) {
          const Eigen::VectorXd gl = J->g[j].transpose() * lambda;
          for (int c = 0; c < n; ++c) plan[j][c] = gl[c] >= 0 ? d.w[c] : -d.w[c];
          lambda = J->phi[j].transpose() * lambda;
        }
        for (int c = 0; c < n; ++c) x[c] = lambda[c] >= 0 ? d.sets[0].hi[c] : d.sets[0].lo[c];
        run([&](int k, int q) {
          if (k < K) {
            w = plan[k];
            return;
          }
          push_away(d, k, q, fine, x, w);
        });
      }
}

}  // namespace

Tightness measure_tightness(const Dynamics& f, const FunnelController& ctrl, std::vector<std::vector<double>> verified,
                            int runs, std::uint64_t seed) {
  const FunnelData& d = ctrl.data();
  const int n = d.n, m = d.m, T = d.horizon();
  constexpr int kFine = 16, kPieces = 8;
  Tightness t;
  t.verified = std::move(verified);
  t.sampled.assign(static_cast<std::size_t>(T) + 1, std::vector<double>(n, 0.0));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U01(0, 1);
  std::vector<double> x(n), u(m), w(n), wx(n), next(n);
  // One closed-loop run from x (inputs held over each period, as deployed); `disturb` sets w for
  // fine step q of period k.
  auto run = [&](const std::function<void(int k, int q)>& disturb) {
    if (!ctrl.in_set(x.data(), 0)) return;
    ++t.runs;
    for (int k = 0; k < T; ++k) {
      for (int i = 0; i < n; ++i) t.sampled[k][i] = std::max(t.sampled[k][i], std::fabs(x[i] - d.x_nom[k][i]));
      if (ctrl.input(x.data(), k, u.data()) != ControlStatus::Ok) break;
      for (int q = 0; q < kFine; ++q) {
        disturb(k, q);
        // Drawn at W's largest value; scaled to W(x, u) where W grows with the state or input.
        if (!d.dist.constant()) d.dist.scale(x.data(), u.data(), d.w.data(), w.data(), wx.data());
        rk4_step<double>(f, x.data(), u.data(), w.data(), d.tau / kFine, 1, next.data());
        x = next;
      }
      if (k + 1 == T)
        for (int i = 0; i < n; ++i) t.sampled[T][i] = std::max(t.sampled[T][i], std::fabs(x[i] - d.x_nom[T][i]));
    }
  };
  for (int r = 0; r < runs; ++r) {
    const int mode = r % 4;
    for (int i = 0; i < n; ++i) x[i] = U01(rng) < 0.5 ? d.sets[0].lo[i] : d.sets[0].hi[i];
    run([&](int k, int q) {
      const bool redraw = (mode == 0 && k == 0 && q == 0) || (mode == 1 && q % (kFine / kPieces) == 0) || mode == 2;
      if (redraw)
        for (int i = 0; i < n; ++i) w[i] = (U01(rng) < 0.5 ? -1 : 1) * d.w[i];
      if (mode == 3) push_away(d, k, q, kFine, x, w);
    });
  }
  if (runs > 0) linearized_worst_cases(f, ctrl, kFine, run, x, w);
  std::vector<double> all;
  t.coordinate_median.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    std::vector<double> ratios;
    for (int k = 1; k <= T && k < static_cast<int>(t.verified.size()); ++k) {
      const double s = t.sampled[k][i];
      if (!(s > 1e-9)) continue;
      ratios.push_back(t.verified[k][i] / s);
    }
    t.coordinate_median[i] = median_of(ratios);
    for (double v : ratios) t.max = std::max(t.max, v);
    all.insert(all.end(), ratios.begin(), ratios.end());
  }
  t.median = median_of(all);
  return t;
}

std::string describe(const Tightness& t, const std::vector<std::string>& names) {
  std::ostringstream s;
  s.precision(3);
  s << "median " << t.median << "x, max " << t.max << "x";
  int worst = -1;
  for (int i = 0; i < static_cast<int>(t.coordinate_median.size()); ++i)
    if (worst < 0 || t.coordinate_median[i] > t.coordinate_median[worst]) worst = i;
  if (worst >= 0 && worst < static_cast<int>(names.size()))
    s << " (worst coordinate " << names[worst] << " " << t.coordinate_median[worst] << "x)";
  return s.str();
}

}  // namespace marsyn::funnel
