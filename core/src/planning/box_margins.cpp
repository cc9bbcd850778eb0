#include "marsyn/core/planning/box_margins.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "marsyn/fast_interval.hpp"

namespace marsyn::planning {

// Directed rounding from error-free transformations in round-to-nearest (directed_rounding.hpp,
// docs/soundness.md §2): no rounding-mode switches, which made the Boost.Interval version of
// these loops the bulk of a continuous-time plan check. Each public function holds RN itself.
using fast_detail::add_down;
using fast_detail::add_up;
using fast_detail::div_down;
using fast_detail::mul_down;
using fast_detail::mul_up;
using fast_detail::sqrt_down;
using fast_detail::sqrt_up;
using fast_detail::sub_down;
using fast_detail::sub_up;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

bool finite_box(const Box& b) {
  for (int i = 0; i < b.dim(); ++i)
    if (!std::isfinite(b.lo[i]) || !std::isfinite(b.hi[i])) return false;
  return true;
}

// For any direction a: min_{b in B} a.b - max_{p in P} a.p <= a.(b - p) <= ||a||_* ||b - p|| for
// every b in B, p in P (Hölder, ||.||_* the dual norm: 1-norm for inf, 2-norm for 2), so
// gap(a) / ||a||_* is a lower bound of dist(B, P) whatever a is. Directions therefore need no
// exact arithmetic; only gap and the norm are evaluated with directed rounding. For convex
// polygons the best direction is among the candidates used below (edge normals; for the 2-norm
// also vertex-to-vertex directions), which makes the bound tight up to rounding.
double separation(const Polygon& A, const Polygon& P, const Eigen::Vector2d& a, Norm norm) {
  const double ax = a.x(), ay = a.y();
  if (!(ax != 0.0 || ay != 0.0) || !std::isfinite(ax) || !std::isfinite(ay)) return -kInf;
  double min_a = kInf, max_p = -kInf;
  for (const auto& v : A) min_a = std::min(min_a, add_down(mul_down(ax, v.x()), mul_down(ay, v.y())));
  for (const auto& v : P) max_p = std::max(max_p, add_up(mul_up(ax, v.x()), mul_up(ay, v.y())));
  const double gap = sub_down(min_a, max_p);
  if (!std::isfinite(gap)) return -kInf;
  double len_lo, len_up;
  if (norm == Norm::Inf) {
    len_lo = add_down(std::abs(ax), std::abs(ay));
    len_up = add_up(std::abs(ax), std::abs(ay));
  } else {
    len_lo = sqrt_down(add_down(mul_down(ax, ax), mul_down(ay, ay)));
    len_up = sqrt_up(add_up(mul_up(ax, ax), mul_up(ay, ay)));
  }
  if (!(len_lo > 0)) return gap >= 0 ? 0.0 : -kInf;
  // The lower end of gap / [len_lo, len_up]: divide by the largest length when gap >= 0.
  return div_down(gap, gap >= 0 ? len_up : len_lo);
}

Polygon corners(const Box& b) {
  return {{b.lo[0], b.lo[1]}, {b.hi[0], b.lo[1]}, {b.hi[0], b.hi[1]}, {b.lo[0], b.hi[1]}};
}

// Lower bound of dist(A, P) for convex polygons (negative or -inf when they meet).
double polygon_distance(const Polygon& A, const Polygon& P, Norm norm) {
  double best = -kInf;
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

// Gap between the boxes along coordinate c (lower bound; negative when they overlap there).
double gap_down(const Box& a, const Box& b, int c) {
  return std::max(sub_down(a.lo[c], b.hi[c]), sub_down(b.lo[c], a.hi[c]));
}

// Lower bound of the distance between two boxes (negative: overlap depth, indicative only).
// In 3-D the z gap joins: the distance between boxes separates by coordinate in both norms.
double box_distance(const Box& a, const Box& b, Norm norm) {
  const double gx = gap_down(a, b, 0), gy = gap_down(a, b, 1);
  if (std::min(a.dim(), b.dim()) >= 3) {
    const double gz = gap_down(a, b, 2);
    if (norm == Norm::Inf || (gx <= 0 && gy <= 0 && gz <= 0)) return std::max({gx, gy, gz});
    const double px = std::max(0.0, gx), py = std::max(0.0, gy), pz = std::max(0.0, gz);
    return sqrt_down(add_down(add_down(mul_down(px, px), mul_down(py, py)), mul_down(pz, pz)));
  }
  if (norm == Norm::Inf || (gx <= 0 && gy <= 0)) return std::max(gx, gy);
  const double px = std::max(0.0, gx), py = std::max(0.0, gy);
  return sqrt_down(add_down(mul_down(px, px), mul_down(py, py)));
}

}  // namespace

double box_obstacle_margin(const Box& w, const Polygon& obstacle, double delta, Norm norm) {
  if (obstacle.size() < 3) return kInf;
  if (!finite_box(w)) return -kInf;
  const RoundToNearestScope nearest;
  return sub_down(polygon_distance(corners(w), obstacle, norm), delta);
}

double box_obstacle_margin(const Box& w, const Obstacle& o, double delta, Norm norm) {
  // An axis-aligned box obstacle (the loader's `box`, stored lo-lo, hi-lo, hi-hi, lo-hi): the
  // distance between two boxes separates by coordinate, a few directed operations instead of the
  // polygon's 12-28 separating directions (the bulk of a small team's continuous-time check).
  if (o.is_box && o.vertices.size() == 4) {
    if (!finite_box(w)) return -kInf;
    const bool space = w.dim() >= 3 && o.z_bounded();
    Box b{Eigen::VectorXd(space ? 3 : 2), Eigen::VectorXd(space ? 3 : 2)};
    b.lo.head<2>() = o.vertices[0];
    b.hi.head<2>() = o.vertices[2];
    if (space) {
      b.lo[2] = o.z_lo;
      b.hi[2] = o.z_hi;
    }
    const RoundToNearestScope nearest;
    return sub_down(box_distance(w, b, norm), delta);
  }
  if (w.dim() < 3 || !o.z_bounded()) return box_obstacle_margin(w, o.vertices, delta, norm);
  if (o.vertices.size() < 3) return kInf;
  if (!finite_box(w)) return -kInf;
  const RoundToNearestScope nearest;
  // s and h are lower bounds of the x-y and z distances (each negative when they overlap there);
  // the combination is monotone in both, so it stays a lower bound of the prism's distance.
  const double s = polygon_distance(corners(w), o.vertices, norm);
  const double h = std::max(sub_down(o.z_lo, w.hi[2]), sub_down(w.lo[2], o.z_hi));
  double d;
  if (s > 0 && h > 0)
    d = norm == Norm::Inf ? std::max(s, h) : sqrt_down(add_down(mul_down(s, s), mul_down(h, h)));
  else
    d = std::max(s, h);
  return sub_down(d, delta);
}

double box_pair_margin(const Box& a, const Box& b, double delta, Norm norm) {
  if (!finite_box(a) || !finite_box(b)) return -kInf;
  const RoundToNearestScope nearest;
  return sub_down(box_distance(a, b, norm), delta);
}

double box_formation_margin(const Box& a, const Box& b, double lambda, double mu) {
  if (!finite_box(a) || !finite_box(b)) return -kInf;
  const RoundToNearestScope nearest;
  // Smallest distance: as for the pair margin (2-norm); largest: the farthest corners.
  const double dmin = std::max(0.0, box_distance(a, b, Norm::Two));
  double far2 = 0.0;
  for (int c = 0; c < std::min(a.dim(), b.dim()); ++c) {
    const double s = std::max(std::abs(sub_up(a.hi[c], b.lo[c])), std::abs(sub_up(b.hi[c], a.lo[c])));
    // |a.hi - b.lo| <= max(|up|, |down|); the larger of the upward-rounded magnitudes bounds both.
    const double s2 = std::max(s, std::max(std::abs(sub_down(a.hi[c], b.lo[c])), std::abs(sub_down(b.hi[c], a.lo[c]))));
    far2 = add_up(far2, mul_up(s2, s2));
  }
  const double dmax = sqrt_up(far2);
  const double band_lo = add_up(lambda, -mu), band_hi = add_down(lambda, mu);
  return std::min(sub_down(dmin, band_lo), sub_down(band_hi, dmax));
}

double obstacle_clearance_up(const Problem& problem, int a) {
  const RoundToNearestScope nearest;
  return add_up(problem.obstacle_delta(), problem.body_spec(a).radius);
}

double pair_clearance_up(const Problem& problem, int a, int b) {
  const RoundToNearestScope nearest;
  return add_up(add_up(problem.delta, problem.body_spec(a).radius), problem.body_spec(b).radius);
}

double box_requirement_margin(const Problem& problem, const Requirement& r, const std::vector<Box>& ws) {
  const Box& a = ws[static_cast<size_t>(r.a)];
  switch (r.kind) {
    case Requirement::Obstacle:
      return box_obstacle_margin(a, problem.obstacles[static_cast<size_t>(r.b)], obstacle_clearance_up(problem, r.a),
                                 problem.delta_norm);
    case Requirement::Collision:
      return box_pair_margin(a, ws[static_cast<size_t>(r.b)], pair_clearance_up(problem, r.a, r.b), problem.delta_norm);
    case Requirement::Formation: break;
  }
  const FormationPair& f = problem.formation[static_cast<size_t>(r.index)];
  return box_formation_margin(a, ws[static_cast<size_t>(r.b)], f.lambda, f.mu);
}

// Agent a's workspace box over the state box `grown` (xb, pb: scratch).
void workspace_box(const AgentSpec& a, int D, const Box& grown, std::vector<Interval>& xb, std::vector<Interval>& pb,
                   Box& out) {
  if (a.workspace.linear()) {  // exact up to one directed addition, no interval type needed
    const RoundToNearestScope nearest;
    for (int c = 0; c < D; ++c) {
      const int at = a.workspace.index[c];
      const double off = a.workspace.offset[c];
      out.lo[c] = at >= 0 ? fast_detail::add_down(grown.lo[at], off) : off;
      out.hi[c] = at >= 0 ? fast_detail::add_up(grown.hi[at], off) : off;
    }
    return;
  }
  xb.resize(a.n());
  for (int c = 0; c < a.n(); ++c) xb[c] = Interval(grown.lo[c], grown.hi[c]);
  pb.resize(kMaxWorkspaceDim);
  workspace_point(*a.dynamics, a.workspace, xb.data(), pb.data());
  for (int c = 0; c < 2; ++c) {
    out.lo[c] = pb[c].lower();
    out.hi[c] = pb[c].upper();
  }
}

Box workspace_box(const AgentSpec& a, const Box& state) {
  const int D = a.workspace.dim();
  Box out{Eigen::VectorXd::Zero(D), Eigen::VectorXd::Zero(D)};
  std::vector<Interval> xb, pb;
  workspace_box(a, D, state, xb, pb, out);
  return out;
}

double box_inside_margin(const Box& box, const Box& X, int coord) {
  double m = kInf;
  const RoundToNearestScope nearest;
  for (int i = 0; i < X.dim(); ++i) {
    if (coord >= 0 && i != coord) continue;
    if (!std::isfinite(box.lo[i]) || !std::isfinite(box.hi[i])) return -kInf;
    m = std::min(m, sub_down(box.lo[i], X.lo[i]));
    m = std::min(m, sub_down(X.hi[i], box.hi[i]));
  }
  return m;
}

}  // namespace marsyn::planning
