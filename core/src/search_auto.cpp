#include "marsyn/core/search_auto.hpp"

#include <algorithm>
#include <cmath>

#include "marsyn/core/problem/auto_tube.hpp"
#include "marsyn/number_text.hpp"

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

Eigen::VectorXd kept_tube(const TrackResult& r, const NominalTrajectory& nom, double tau) {
  const auto n = nom.x.empty() ? 0 : nom.x.front().size();
  if (n > 0 && r.stats.tube_kept.size() == static_cast<std::size_t>(n))
    return Eigen::Map<const Eigen::VectorXd>(r.stats.tube_kept.data(), n);
  return r.controller ? kept_tube(*r.controller, nom, tau) : Eigen::VectorXd();
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

std::string auto_eps_rule_text(const AgentSpec& a, const Eigen::VectorXd& kept, double tau, const Eigen::VectorXd& first,
                               const Eigen::VectorXd& next, const std::vector<std::string>& names) {
  std::vector<std::string> floor, push, cap;
  for (Eigen::Index i = 0; i < next.size() && i < kept.size(); ++i) {
    const std::string name = i < static_cast<Eigen::Index>(names.size()) ? names[static_cast<std::size_t>(i)] : "x" + std::to_string(i);
    if (next[i] == (1 + kAutoEpsMargin) * kept[i]) continue;
    if (next[i] == a.tube.eps[i]) cap.push_back(name);
    else if (next[i] == kAutoEpsFloor * first[i]) floor.push_back(name);
    else if (next[i] == a.tube.w[i] * tau) push.push_back(name);
  }
  auto join = [](const std::vector<std::string>& v) {
    std::string s;
    for (std::size_t k = 0; k < v.size(); ++k) s += (k ? ", " : "") + v[k];
    return s;
  };
  std::string out = "+" + std::to_string(static_cast<int>(100 * kAutoEpsMargin)) + " %";
  if (!floor.empty()) out += "; " + number_text(kAutoEpsFloor, 3) + " of the first value in " + join(floor);
  if (!push.empty()) out += "; the disturbance's push w tau in " + join(push);
  if (!cap.empty()) out += "; unchanged in " + join(cap);
  return out;
}

}  // namespace marsyn::search
