#pragma once
// Planar geometry, the one module for both norms: convex polygons, their Minkowski sum with an
// axis-aligned box, the differentiable Euclidean signed distance the planners' constraints use,
// and the exact signed distances in either norm that the real specification is judged by
// (spec monitor, verification, certification's margins are in box_margins).
#include <vector>

#include <Eigen/Core>

namespace marsyn::planning {

using Polygon = std::vector<Eigen::Vector2d>;  // convex, counter-clockwise

// Convex hull (counter-clockwise, no collinear points) of a point set.
Polygon convex_hull(std::vector<Eigen::Vector2d> points);

// P + [-rx, rx] x [-ry, ry]. For a point p, dist_inf(p, P) >= r holds exactly when p lies outside
// the interior of P grown by the box (r, r); growing by the workspace margin box as well makes the
// condition hold for every point of p's margin box, with no conservatism.
Polygon grow_by_box(const Polygon& poly, double rx, double ry);

// Euclidean signed distance from p to the polygon (negative inside) and its gradient in p
// (a unit vector; for points inside, the outward normal of the nearest edge).
double signed_distance(const Polygon& poly, const Eigen::Vector2d& p, Eigen::Vector2d* grad = nullptr);

// Signed distance from p to a convex polygon (negative inside) in the inf-norm, exactly.
double signed_distance_inf(const Polygon& ccw_polygon, const Eigen::Vector2d& p);
// The same in the Euclidean norm.
double signed_distance_two(const Polygon& ccw_polygon, const Eigen::Vector2d& p);

}  // namespace marsyn::planning
