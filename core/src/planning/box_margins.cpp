#include "marsyn/core/planning/box_margins.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "marsyn/interval.hpp"

namespace marsyn::planning {

namespace {

// For any direction a: min_{b in B} a.b - max_{p in P} a.p <= a.(b - p) <= ||a||_* ||b - p|| for
// every b in B, p in P (Hölder, ||.||_* the dual norm: 1-norm for inf, 2-norm for 2), so
// gap(a) / ||a||_* is a lower bound of dist(B, P) whatever a is. Directions therefore need no
// exact arithmetic; only gap and the norm are evaluated in intervals. For convex polygons the
// best direction is among the candidates used below (edge normals; for the 2-norm also
// vertex-to-vertex directions), which makes the bound tight up to rounding.
double separation(const Polygon& A, const Polygon& P, const Eigen::Vector2d& a, Norm norm) {
  if (!(a.x() != 0.0 || a.y() != 0.0) || !std::isfinite(a.x()) || !std::isfinite(a.y()))
    return -std::numeric_limits<double>::infinity();
  double min_a = std::numeric_limits<double>::infinity(), max_p = -std::numeric_limits<double>::infinity();
  for (const auto& v : A) min_a = std::min(min_a, (Interval(a.x()) * v.x() + Interval(a.y()) * v.y()).lower());
  for (const auto& v : P) max_p = std::max(max_p, (Interval(a.x()) * v.x() + Interval(a.y()) * v.y()).upper());
  const Interval gap = Interval(min_a) - Interval(max_p);
  const Interval len = norm == Norm::Inf ? abs(Interval(a.x())) + abs(Interval(a.y()))
                                         : sqrt(square(Interval(a.x())) + square(Interval(a.y())));
  // gap / len bounded below: the lower end of the quotient interval.
  return (gap / len).lower();
}

Polygon corners(const Box& b) {
  return {{b.lo[0], b.lo[1]}, {b.hi[0], b.lo[1]}, {b.hi[0], b.hi[1]}, {b.lo[0], b.hi[1]}};
}

// Lower bound of dist(A, P) for convex polygons (negative or -inf when they meet).
double polygon_distance(const Polygon& A, const Polygon& P, Norm norm) {
  double best = -std::numeric_limits<double>::infinity();
  auto edges = [&](const Polygon& Q, bool q_is_a) {
    const size_t k = Q.size();
    for (size_t e = 0; e < k; ++e) {
      const Eigen::Vector2d d = Q[(e + 1) % k] - Q[e];
      const Eigen::Vector2d out(d.y(), -d.x());  // outward normal of a counter-clockwise polygon
      best = std::max(best, q_is_a ? separation(A, P, -out, norm) : separation(A, P, out, norm));
    }
  };
  for (const auto& a : {Eigen::Vector2d(1, 0), Eigen::Vector2d(-1, 0), Eigen::Vector2d(0, 1), Eigen::Vector2d(0, -1)})
    best = std::max(best, separation(A, P, a, norm));
  edges(P, false);
  edges(A, true);
  if (norm == Norm::Two)
    for (const auto& p : P)
      for (const auto& b : A) best = std::max(best, separation(A, P, b - p, norm));
  return best;
}

}  // namespace

double box_obstacle_margin(const Box& w, const Polygon& obstacle, double delta, Norm norm) {
  if (obstacle.size() < 3) return std::numeric_limits<double>::infinity();
  const double d = polygon_distance(corners(w), obstacle, norm);
  return (Interval(d) - Interval(delta)).lower();
}

double box_pair_margin(const Box& a, const Box& b, double delta, Norm norm) {
  // Gaps along x and y (exact directions): dist_inf = max(gx, gy); dist_2 = |(gx+, gy+)|.
  Interval g[2];
  for (int c = 0; c < 2; ++c) {
    const Interval g1 = Interval(a.lo[c]) - Interval(b.hi[c]), g2 = Interval(b.lo[c]) - Interval(a.hi[c]);
    g[c] = Interval(std::max(g1.lower(), g2.lower()), std::max(g1.upper(), g2.upper()));
  }
  if (norm == Norm::Inf) return (Interval(std::max(g[0].lower(), g[1].lower())) - Interval(delta)).lower();
  const Interval px = Interval(std::max(0.0, g[0].lower())), py = Interval(std::max(0.0, g[1].lower()));
  if (px.lower() <= 0 && py.lower() <= 0) return (Interval(std::max(g[0].lower(), g[1].lower())) - Interval(delta)).lower();
  return (sqrt(square(px) + square(py)) - Interval(delta)).lower();
}

double box_formation_margin(const Box& a, const Box& b, double lambda, double mu) {
  // Smallest distance: as for the pair margin (2-norm, delta 0); largest: the farthest corners.
  const double dmin = std::max(0.0, box_pair_margin(a, b, 0.0, Norm::Two));
  Interval far2(0.0);
  for (int c = 0; c < 2; ++c) {
    const Interval s = max(abs(Interval(a.hi[c]) - Interval(b.lo[c])), abs(Interval(b.hi[c]) - Interval(a.lo[c])));
    far2 += square(s);
  }
  const double dmax = sqrt(far2).upper();
  const Interval lo = Interval(lambda) - Interval(mu), hi = Interval(lambda) + Interval(mu);
  return std::min((Interval(dmin) - lo).lower(), (hi - Interval(dmax)).lower());
}

double box_inside_margin(const Box& box, const Box& X) {
  double m = std::numeric_limits<double>::infinity();
  for (int i = 0; i < X.dim(); ++i) {
    m = std::min(m, (Interval(box.lo[i]) - Interval(X.lo[i])).lower());
    m = std::min(m, (Interval(X.hi[i]) - Interval(box.hi[i])).lower());
  }
  return m;
}

}  // namespace marsyn::planning
