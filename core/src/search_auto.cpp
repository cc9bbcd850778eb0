#include "marsyn/core/search_auto.hpp"

#include <algorithm>
#include <cmath>

#include "marsyn/core/problem/auto_tube.hpp"

namespace marsyn::search {

Eigen::VectorXd kept_tube(const Controller& c, const NominalTrajectory& nom, double tau) {
  const auto& encl = c.period_enclosures();
  if (encl.empty() || nom.x.empty()) return {};
  const Eigen::Index n = nom.x.front().size();
  Eigen::VectorXd kept = Eigen::VectorXd::Zero(n);
  auto widen = [&](const PeriodEnclosure& e, std::size_t k) {
    if (k >= nom.x.size() || e.state.dim() != n) return;
    kept = kept.cwiseMax((e.state.hi - nom.x[k]).cwiseMax(nom.x[k] - e.state.lo));
  };
  const double tol = 1e-9 * std::max(1.0, tau);
  for (const auto& e : encl) {
    if (e.step < 0) continue;
    const auto k = static_cast<std::size_t>(e.step);
    if (std::abs(e.t0 - e.step * tau) <= tol * (1 + e.step)) widen(e, k);
    if (std::abs(e.t1 - (e.step + 1) * tau) <= tol * (2 + e.step)) widen(e, k + 1);
  }
  return kept;
}

Eigen::VectorXd narrower_auto_eps(const AgentSpec& a, const Eigen::VectorXd& kept, double tau,
                                  const Eigen::VectorXd& first) {
  if (kept.size() != a.tube.eps.size() || !kept.allFinite() || first.size() != kept.size()) return {};
  Eigen::VectorXd next =
      ((1 + kAutoEpsMargin) * kept).cwiseMax(a.tube.w * tau).cwiseMax(kAutoEpsFloor * first).cwiseMin(a.tube.eps);
  for (Eigen::Index i = 0; i < next.size(); ++i)
    if (!(next[i] > 0)) next[i] = a.tube.eps[i];
  return (next.array() <= 0.9 * a.tube.eps.array()).any() ? next : Eigen::VectorXd();
}

}  // namespace marsyn::search
