#include "marsyn/core/planning/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace marsyn::planning {

namespace {
double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}
}  // namespace

Polygon convex_hull(std::vector<Eigen::Vector2d> pts) {
  std::sort(pts.begin(), pts.end(), [](const auto& a, const auto& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (pts.size() < 3) return pts;
  Polygon hull(2 * pts.size());
  size_t k = 0;
  for (const auto& p : pts) {  // lower chain (Andrew's monotone chain)
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0) --k;
    hull[k++] = p;
  }
  for (size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  hull.resize(k - 1);
  return hull;
}

Polygon grow_by_box(const Polygon& poly, double rx, double ry) {
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(poly.size() * 4);
  for (const auto& v : poly)
    for (double sx : {-1.0, 1.0})
      for (double sy : {-1.0, 1.0}) pts.emplace_back(v.x() + sx * rx, v.y() + sy * ry);
  return convex_hull(std::move(pts));
}

PolygonEdges::PolygonEdges(const Polygon& poly) {
  const size_t n = poly.size();
  a.reserve(n), e.reserve(n), normal.reserve(n), len2.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    a.push_back(poly[i]);
    e.push_back(poly[(i + 1) % n] - poly[i]);
    len2.push_back(e.back().squaredNorm());
    normal.push_back(Eigen::Vector2d(e.back().y(), -e.back().x()) / std::sqrt(len2.back()));  // outward
  }
}

double signed_distance(const Polygon& poly, const Eigen::Vector2d& p, Eigen::Vector2d* grad) {
  return signed_distance(PolygonEdges(poly), p, grad);
}

double signed_distance(const PolygonEdges& poly, const Eigen::Vector2d& p, Eigen::Vector2d* grad) {
  const size_t n = poly.a.size();
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d best_dir(1, 0);
  // For a convex CCW polygon p is inside iff it is left of every edge; the largest signed edge
  // distance is then minus the depth.
  double max_edge = -std::numeric_limits<double>::infinity();
  Eigen::Vector2d max_normal(1, 0);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = poly.a[i];
    const Eigen::Vector2d& e = poly.e[i];
    const Eigen::Vector2d& normal = poly.normal[i];
    const double side = normal.dot(p - a);
    if (side > max_edge) {
      max_edge = side;
      max_normal = normal;
    }
    const double t = std::clamp((p - a).dot(e) / poly.len2[i], 0.0, 1.0);
    const Eigen::Vector2d diff = p - (a + t * e);
    const double d = diff.norm();
    if (d < best) {
      best = d;
      best_dir = d > 0 ? Eigen::Vector2d(diff / d) : normal;
    }
  }
  if (max_edge <= 0) {  // inside (or on the boundary)
    if (grad) *grad = max_normal;
    return max_edge;
  }
  if (grad) *grad = best_dir;
  return best;
}

// The real specification's distances (spec monitor, verification): a point against a convex
// polygon in the problem's norm.
namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

bool inside(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  for (std::size_t i = 0; i < poly.size(); ++i)
    if (cross(poly[(i + 1) % poly.size()] - poly[i], p - poly[i]) < 0) return false;
  return true;
}

// min over t in [0, 1] of |p - (a + t (b - a))|_inf. The objective is convex and piecewise
// linear in t; its minimum is at an end point or where a component vanishes or the two
// components have equal magnitude.
double segment_distance_inf(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  const Eigen::Vector2d d0 = p - a, e = b - a;  // d(t) = d0 - t e
  auto f = [&](double t) {
    const Eigen::Vector2d d = d0 - t * e;
    return std::max(std::abs(d.x()), std::abs(d.y()));
  };
  double best = std::min(f(0.0), f(1.0));
  auto consider = [&](double num, double den) {
    if (std::abs(den) < 1e-300) return;
    const double t = num / den;
    if (t > 0.0 && t < 1.0) best = std::min(best, f(t));
  };
  consider(d0.x(), e.x());                  // dx(t) = 0
  consider(d0.y(), e.y());                  // dy(t) = 0
  consider(d0.x() - d0.y(), e.x() - e.y());  // dx = dy
  consider(d0.x() + d0.y(), e.x() + e.y());  // dx = -dy
  return best;
}

double segment_distance_two(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  const Eigen::Vector2d e = b - a;
  const double t = std::clamp((p - a).dot(e) / std::max(e.squaredNorm(), 1e-300), 0.0, 1.0);
  return (p - (a + t * e)).norm();
}

template <class SegmentDistance, class Depth>
double signed_distance(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p, SegmentDistance seg,
                       Depth depth) {
  const std::size_t n = poly.size();
  if (inside(poly, p)) {
    // Inside: the smallest move that exits across some edge's supporting line.
    double d = 1e300;
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector2d e = poly[(i + 1) % n] - poly[i];
      const Eigen::Vector2d normal = Eigen::Vector2d(e.y(), -e.x()).normalized();  // outward for CCW
      const double h = (poly[i] - p).dot(normal);                                     // >= 0 inside
      d = std::min(d, depth(h, normal));
    }
    return -d;
  }
  double d = 1e300;
  for (std::size_t i = 0; i < n; ++i) d = std::min(d, seg(poly[i], poly[(i + 1) % n], p));
  return d;
}

}  // namespace

double signed_distance_inf(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  // An inf-norm ball of radius r reaches a line at Euclidean distance h when r |n|_1 = h.
  return signed_distance(poly, p, segment_distance_inf,
                         [](double h, const Eigen::Vector2d& n) { return h / n.lpNorm<1>(); });
}

double signed_distance_two(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  return signed_distance(poly, p, segment_distance_two, [](double h, const Eigen::Vector2d&) { return h; });
}

double prism_combine(double s, double h, bool inf_norm) {
  if (s > 0 && h > 0) return inf_norm ? std::max(s, h) : std::sqrt(s * s + h * h);
  return std::max(s, h);
}

double signed_distance_inf(const Polygon& poly, double z_lo, double z_hi, const Eigen::Vector3d& p) {
  return prism_combine(signed_distance_inf(poly, Eigen::Vector2d(p.x(), p.y())), z_gap(p.z(), z_lo, z_hi), true);
}

double signed_distance_two(const Polygon& poly, double z_lo, double z_hi, const Eigen::Vector3d& p) {
  return prism_combine(signed_distance_two(poly, Eigen::Vector2d(p.x(), p.y())), z_gap(p.z(), z_lo, z_hi), false);
}

double signed_distance(const Polygon& poly, double z_lo, double z_hi, const Eigen::Vector3d& p, Eigen::Vector3d* grad) {
  return signed_distance(PolygonEdges(poly), z_lo, z_hi, p, grad);
}

double signed_distance(const PolygonEdges& poly, double z_lo, double z_hi, const Eigen::Vector3d& p, Eigen::Vector3d* grad) {
  Eigen::Vector2d g2;
  const double s = signed_distance(poly, Eigen::Vector2d(p.x(), p.y()), &g2);
  const double h = z_gap(p.z(), z_lo, z_hi);
  const double dz = z_lo - p.z() > p.z() - z_hi ? -1.0 : 1.0;  // dh/dz
  if (s > 0 && h > 0) {
    const double r = std::sqrt(s * s + h * h);
    if (grad) *grad = Eigen::Vector3d(s * g2.x() / r, s * g2.y() / r, h * dz / r);
    return r;
  }
  if (h > s) {
    if (grad) *grad = Eigen::Vector3d(0.0, 0.0, dz);
    return h;
  }
  if (grad) *grad = Eigen::Vector3d(g2.x(), g2.y(), 0.0);
  return s;
}

}  // namespace marsyn::planning
