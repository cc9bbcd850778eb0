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

double signed_distance(const Polygon& poly, const Eigen::Vector2d& p, Eigen::Vector2d* grad) {
  const size_t n = poly.size();
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d best_dir(1, 0);
  // For a convex CCW polygon p is inside iff it is left of every edge; the largest signed edge
  // distance is then minus the depth.
  double max_edge = -std::numeric_limits<double>::infinity();
  Eigen::Vector2d max_normal(1, 0);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d a = poly[i], b = poly[(i + 1) % n];
    const Eigen::Vector2d e = b - a;
    const double len2 = e.squaredNorm();
    const Eigen::Vector2d normal = Eigen::Vector2d(e.y(), -e.x()) / std::sqrt(len2);  // outward
    const double side = normal.dot(p - a);
    if (side > max_edge) {
      max_edge = side;
      max_normal = normal;
    }
    const double t = std::clamp((p - a).dot(e) / len2, 0.0, 1.0);
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

}  // namespace marsyn::planning
