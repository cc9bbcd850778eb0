#include "marsyn/core/planning/flow_enclosure.hpp"

#include "marsyn/apriori_enclosure.hpp"

#include <algorithm>
#include <cmath>

#include "marsyn/fast_interval.hpp"

namespace marsyn::planning {

namespace {

bool finite(const FastInterval& v) { return std::isfinite(v.lower()) && std::isfinite(v.upper()); }

}  // namespace

bool flow_boxes(const Dynamics& f, const Box& start, const Eigen::VectorXd& u, const Eigen::VectorXd& w, double tau,
                int parts, std::vector<Box>& out) {
  const int n = f.state_dim(), m = f.input_dim();
  if (start.dim() != n || w.size() != n || u.size() != m || parts < 1 || !(tau > 0)) return false;
  // FastInterval (directed rounding without mode switches) needs round-to-nearest, as do the
  // model's plain double operations inside its interval field.
  const RoundToNearestScope nearest;
  std::vector<FastInterval> X(n), U(m), B(n), FB(n), cand(n), W(n);
  for (int i = 0; i < n; ++i) {
    if (!(start.lo[i] <= start.hi[i]) || !std::isfinite(start.lo[i]) || !std::isfinite(start.hi[i])) return false;
    X[i] = FastInterval(start.lo[i], start.hi[i]);
    W[i] = FastInterval(-std::abs(w[i]), std::abs(w[i]));
  }
  for (int j = 0; j < m; ++j) U[j] = FastInterval(u[j]);
  const FastInterval h = FastInterval(tau) / FastInterval(static_cast<double>(parts));
  const FastInterval t(0.0, h.upper());
  // Every entry is written below: a caller's boxes of the right shape are reused as they are.
  if (out.size() != static_cast<size_t>(parts) || out[0].lo.size() != n || out[0].hi.size() != n)
    out.assign(static_cast<size_t>(parts), Box{Eigen::VectorXd(n), Eigen::VectorXd(n)});
  for (int s = 0; s < parts; ++s) {
    f.field(X.data(), U.data(), FB.data());
    for (int i = 0; i < n; ++i) B[i] = X[i] + t * (FB[i] + W[i]);
    bool found = false, blown = false;  // blown: the boxes left the field's domain; try the other method
    for (int it = 0; it < 30 && !found && !blown; ++it) {
      // Inflation (growing each round) makes the containment test succeed for a smooth field.
      const double grow = 0.1 * (1 + it / 10);
      for (int i = 0; i < n; ++i) {
        const double r = grow * width(B[i]) + 1e-12 * (1.0 + mag(B[i]));
        B[i] = FastInterval(B[i].lower() - r, B[i].upper() + r);
        if (!finite(B[i])) blown = true;
      }
      if (blown) break;
      f.field(B.data(), U.data(), FB.data());
      found = true;
      for (int i = 0; i < n; ++i) {
        cand[i] = X[i] + t * (FB[i] + W[i]);
        if (!finite(cand[i])) blown = true;
        if (!subset(cand[i], B[i])) found = false;
      }
      if (blown) {
        found = false;
        break;
      }
      if (!found)
        for (int i = 0; i < n; ++i) B[i] = hull(B[i], cand[i]);
    }
    // The shared fixed-point method where inflating every coordinate fails (chains of products
    // started at rest); where the loop above succeeds its boxes are kept as they were.
    if (!found) {
      if (!apriori_enclosure_fixed_point(f, X.data(), U.data(), W.data(), h, 30, cand.data())) return false;
      // The step below needs f over a verified enclosure: the new one.
      B = cand;
      f.field(B.data(), U.data(), FB.data());
    }
    for (int i = 0; i < n; ++i) {
      out[s].lo[i] = cand[i].lower();
      out[s].hi[i] = cand[i].upper();
      // x(t + h) = x(t) + the integral of f + w over the part, which lies in h (F(B) + W).
      const FastInterval next = X[i] + h * (FB[i] + W[i]);
      X[i] = FastInterval(std::max(next.lower(), cand[i].lower()), std::min(next.upper(), cand[i].upper()));
    }
  }
  return true;
}

}  // namespace marsyn::planning
