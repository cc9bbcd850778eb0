#include "marsyn/core/planning/flow_enclosure.hpp"

#include <algorithm>
#include <cmath>

#include "marsyn/interval.hpp"

namespace marsyn::planning {

namespace {

bool finite(const Interval& v) { return std::isfinite(v.lower()) && std::isfinite(v.upper()); }

}  // namespace

bool flow_boxes(const Dynamics& f, const Box& start, const Eigen::VectorXd& u, const Eigen::VectorXd& w, double tau,
                int parts, std::vector<Box>& out) {
  const int n = f.state_dim(), m = f.input_dim();
  if (start.dim() != n || w.size() != n || u.size() != m || parts < 1 || !(tau > 0)) return false;
  std::vector<Interval> X(n), U(m), B(n), FB(n), cand(n), W(n);
  for (int i = 0; i < n; ++i) {
    if (!(start.lo[i] <= start.hi[i])) return false;
    X[i] = Interval(start.lo[i], start.hi[i]);
    W[i] = Interval(-std::abs(w[i]), std::abs(w[i]));
  }
  for (int j = 0; j < m; ++j) U[j] = Interval(u[j]);
  const Interval h = Interval(tau) / Interval(static_cast<double>(parts));
  const Interval t(0.0, h.upper());
  out.assign(static_cast<size_t>(parts), Box{Eigen::VectorXd(n), Eigen::VectorXd(n)});
  for (int s = 0; s < parts; ++s) {
    f.field(X.data(), U.data(), FB.data());
    for (int i = 0; i < n; ++i) B[i] = X[i] + t * (FB[i] + W[i]);
    bool found = false;
    for (int it = 0; it < 20 && !found; ++it) {
      for (int i = 0; i < n; ++i) {
        const double r = 0.1 * width(B[i]) + 1e-12 * (1.0 + norm(B[i]));
        B[i] = Interval(B[i].lower() - r, B[i].upper() + r);
        if (!finite(B[i])) return false;
      }
      f.field(B.data(), U.data(), FB.data());
      found = true;
      for (int i = 0; i < n; ++i) {
        cand[i] = X[i] + t * (FB[i] + W[i]);
        if (!finite(cand[i])) return false;
        if (!subset(cand[i], B[i])) found = false;
      }
      if (!found)
        for (int i = 0; i < n; ++i) B[i] = hull(B[i], cand[i]);
    }
    if (!found) return false;
    for (int i = 0; i < n; ++i) {
      out[s].lo[i] = cand[i].lower();
      out[s].hi[i] = cand[i].upper();
      // x(t + h) = x(t) + integral of f over the part, which lies in h times the hull of F(B).
      const Interval next = X[i] + h * (FB[i] + W[i]);
      X[i] = Interval(std::max(next.lower(), cand[i].lower()), std::min(next.upper(), cand[i].upper()));
    }
  }
  return true;
}

}  // namespace marsyn::planning
