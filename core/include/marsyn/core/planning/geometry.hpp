#pragma once
// Planar geometry, the one module for both norms: convex polygons, their Minkowski sum with an
// axis-aligned box, the differentiable Euclidean signed distance the planners' constraints use,
// and the exact signed distances in either norm that the real specification is judged by
// (spec monitor, verification, certification's margins are in box_margins).
#include <algorithm>
#include <vector>

#include <Eigen/Core>

namespace marsyn::planning {

using Polygon = std::vector<Eigen::Vector2d>;  // convex, counter-clockwise

// Workspace points have 3 coordinates (z = 0 in the plane, where no obstacle bounds z): one
// formula per requirement for both.
using Point = Eigen::Vector3d;

// |d|_2, through the plane's own expression when d.z = 0 (2-D results bit for bit).
inline double distance2(const Point& d) {
  return d.z() == 0.0 ? Eigen::Vector2d(d.x(), d.y()).norm() : d.norm();
}

// Convex hull (counter-clockwise, no collinear points) of a point set.
Polygon convex_hull(std::vector<Eigen::Vector2d> points);

// P + [-rx, rx] x [-ry, ry]. For a point p, dist_inf(p, P) >= r holds exactly when p lies outside
// the interior of P grown by the box (r, r); growing by the workspace margin box as well makes the
// condition hold for every point of p's margin box, with no conservatism.
Polygon grow_by_box(const Polygon& poly, double rx, double ry);

// Euclidean signed distance from p to the polygon (negative inside) and its gradient in p
// (a unit vector; for points inside, the outward normal of the nearest edge).
double signed_distance(const Polygon& poly, const Eigen::Vector2d& p, Eigen::Vector2d* grad = nullptr);

// A polygon's edges (start a, direction e = b - a, |e|^2) and outward unit normals, computed
// once for a polygon evaluated many times (an obstacle row at every knot and interior point):
// the per-edge square root and divisions were most of signed_distance. Same values bit for bit.
struct PolygonEdges {
  PolygonEdges() = default;
  explicit PolygonEdges(const Polygon& poly);
  std::vector<Eigen::Vector2d> a, e, normal;
  std::vector<double> len2;
};
double signed_distance(const PolygonEdges& edges, const Eigen::Vector2d& p, Eigen::Vector2d* grad = nullptr);

// Signed distance from p to a convex polygon (negative inside) in the inf-norm, exactly.
double signed_distance_inf(const Polygon& ccw_polygon, const Eigen::Vector2d& p);
// The same in the Euclidean norm.
double signed_distance_two(const Polygon& ccw_polygon, const Eigen::Vector2d& p);

// A 3-D workspace's obstacles are vertical prisms: a convex polygon in x-y times [z_lo, z_hi]
// (unbounded in the plane, where z plays no part). The distance separates: with s the polygon's
// signed distance at p's x-y and h = max(z_lo - z, z - z_hi) the interval's, the prism's is
// max(s, h) unless both are positive (p beyond an edge and above or below), where it is
// hypot(s, h) in the 2-norm and max(s, h) in the inf-norm. Inside (both <= 0) max(s, h) is minus
// the smallest penetration depth in either norm. With an unbounded interval h = -inf and the
// result is s, bit for bit.
double prism_combine(double s, double h, bool inf_norm);
inline double z_gap(double z, double z_lo, double z_hi) { return std::max(z_lo - z, z - z_hi); }

// Exact signed distances from p to the prism polygon x [z_lo, z_hi].
double signed_distance_inf(const Polygon& ccw_polygon, double z_lo, double z_hi, const Eigen::Vector3d& p);
double signed_distance_two(const Polygon& ccw_polygon, double z_lo, double z_hi, const Eigen::Vector3d& p);

// The planners' Euclidean signed distance to the prism and its gradient in p (3 coordinates);
// C1 outside except where the polygon's own distance is not (its vertices' normals).
double signed_distance(const Polygon& poly, double z_lo, double z_hi, const Eigen::Vector3d& p,
                       Eigen::Vector3d* grad = nullptr);
double signed_distance(const PolygonEdges& edges, double z_lo, double z_hi, const Eigen::Vector3d& p,
                       Eigen::Vector3d* grad = nullptr);

}  // namespace marsyn::planning
