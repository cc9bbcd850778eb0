#include "fcl_distance.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <fcl/fcl.h>

namespace marsyn::fcl_collision {

namespace {

// Inside, FCL gives the depth (its penetration run); the gradient is the outward normal of the
// nearest edge, taken from the polygon itself so that it is exact and unique.
struct Planar {
  std::vector<Eigen::Vector2d> v;  // counter-clockwise
  bool is_box = false;
};

double edge_distance(const Planar& poly, const Eigen::Vector2d& p, Eigen::Vector2d* normal) {
  double best = std::numeric_limits<double>::infinity();
  const size_t k = poly.v.size();
  for (size_t i = 0; i < k; ++i) {
    const Eigen::Vector2d a = poly.v[i], b = poly.v[(i + 1) % k];
    const Eigen::Vector2d e = (b - a).normalized();
    const Eigen::Vector2d out(e.y(), -e.x());  // outward for counter-clockwise order
    const double d = -(p - a).dot(out);        // depth behind this edge
    if (d < best) {
      best = d;
      if (normal) *normal = out;
    }
  }
  return best;
}

}  // namespace

struct FclDistance::Shapes {
  std::vector<Planar> planar;
  std::vector<std::shared_ptr<fcl::CollisionGeometryd>> geometry;
  std::vector<fcl::Transform3d> pose;
  // A sphere of radius 0 is a degenerate case for libccd in FCL 0.7 (measured: the nearest point
  // snapped to a 3-D corner, errors up to 1.5 m), and GST_INDEP's signed distance asserts on
  // overlap. For a convex obstacle the signed distance of a ball is that of its centre minus
  // the radius, on both sides, so a small ball with its radius added back is exact.
  std::shared_ptr<fcl::Sphered> point = std::make_shared<fcl::Sphered>(1e-3);
};

FclDistance::~FclDistance() = default;

std::vector<ParamSpec> FclDistance::param_specs() {
  return {
      {"boxes", ParamType::RealVector, "[]", "4 numbers per box", "axis-aligned boxes: lo_x, lo_y, hi_x, hi_y each"},
      {"polygons", ParamType::RealVector, "[]", "k then 2k numbers per polygon",
       "convex polygons, counter-clockwise: vertex count k, then x_1, y_1, ..., x_k, y_k"},
  };
}

FclDistance::FclDistance(const Params& params) : shapes_(std::make_unique<Shapes>()) {
  const auto boxes = params.reals("boxes", {});
  if (boxes.size() % 4 != 0) throw ParamError("boxes", "expected 4 numbers per box");
  for (size_t i = 0; i < boxes.size(); i += 4) {
    const double x0 = boxes[i], y0 = boxes[i + 1], x1 = boxes[i + 2], y1 = boxes[i + 3];
    if (!(x1 > x0 && y1 > y0)) throw ParamError("boxes", "each box needs lo < hi");
    add_polygon({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, true);
  }
  const auto polys = params.reals("polygons", {});
  for (size_t i = 0; i < polys.size();) {
    const double kd = polys[i];
    const long k = std::lround(kd);
    if (k < 3 || std::abs(kd - k) > 0 || i + 1 + 2 * k > polys.size())
      throw ParamError("polygons", "expected a vertex count of at least 3 followed by that many x, y pairs");
    std::vector<Eigen::Vector2d> v;
    for (long j = 0; j < k; ++j) v.emplace_back(polys[i + 1 + 2 * j], polys[i + 2 + 2 * j]);
    add_polygon(std::move(v), false);
    i += 1 + 2 * k;
  }
}

FclDistance::FclDistance(const std::vector<Obstacle>& obstacles) : shapes_(std::make_unique<Shapes>()) {
  for (const auto& o : obstacles) add_polygon(o.vertices, o.is_box);
}

Params FclDistance::params_for(const std::vector<Obstacle>& obstacles) {
  std::vector<double> polys;
  for (const auto& o : obstacles) {
    polys.push_back(static_cast<double>(o.vertices.size()));
    for (const auto& v : o.vertices) {
      polys.push_back(v.x());
      polys.push_back(v.y());
    }
  }
  Params p;
  p.set("polygons", polys);
  return p;
}

int FclDistance::obstacles() const { return static_cast<int>(shapes_->planar.size()); }

void FclDistance::add_polygon(std::vector<Eigen::Vector2d> v, bool is_box) {
  const size_t k = v.size();
  if (k < 3) throw ParamError("polygons", "a polygon needs at least 3 vertices");
  double area = 0.0;
  for (size_t i = 0; i < k; ++i) area += v[i].x() * v[(i + 1) % k].y() - v[(i + 1) % k].x() * v[i].y();
  if (area < 0) std::reverse(v.begin(), v.end());
  if (std::abs(area) < 1e-12) throw ParamError("polygons", "a polygon has zero area");
  Eigen::Vector2d lo = v[0], hi = v[0];
  for (const auto& p : v) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  // Taller than the polygon is wide: no interior point is nearer the top or bottom than a side.
  const double half = 1.0 + (hi - lo).norm();
  fcl::Transform3d pose = fcl::Transform3d::Identity();
  std::shared_ptr<fcl::CollisionGeometryd> geom;
  if (is_box) {
    const Eigen::Vector2d c = 0.5 * (lo + hi), s = hi - lo;
    geom = std::make_shared<fcl::Boxd>(s.x(), s.y(), 2 * half);
    pose.translation() = Eigen::Vector3d(c.x(), c.y(), 0.0);
  } else {
    auto verts = std::make_shared<std::vector<Eigen::Vector3d>>();
    for (const auto& p : v) verts->emplace_back(p.x(), p.y(), -half);
    for (const auto& p : v) verts->emplace_back(p.x(), p.y(), half);
    auto faces = std::make_shared<std::vector<int>>();
    const int n = static_cast<int>(k);
    faces->push_back(n);  // bottom, seen from below: clockwise in the plane
    for (int i = n - 1; i >= 0; --i) faces->push_back(i);
    faces->push_back(n);  // top
    for (int i = 0; i < n; ++i) faces->push_back(n + i);
    for (int i = 0; i < n; ++i) {
      const int j = (i + 1) % n;
      faces->insert(faces->end(), {4, i, j, n + j, n + i});
    }
    geom = std::make_shared<fcl::Convexd>(verts, n + 2, faces);
  }
  geom->computeLocalAABB();
  shapes_->planar.push_back({std::move(v), is_box});
  shapes_->geometry.push_back(std::move(geom));
  shapes_->pose.push_back(pose);
}

double FclDistance::distance(int obstacle, const double* p, double* grad) const {
  if (obstacle < 0 || obstacle >= obstacles()) throw std::out_of_range("fcl distance: no such obstacle");
  const Planar& poly = shapes_->planar[obstacle];
  fcl::Transform3d at = fcl::Transform3d::Identity();
  at.translation() = Eigen::Vector3d(p[0], p[1], 0.0);
  fcl::DistanceRequestd req(true, true);
  req.gjk_solver_type = fcl::GST_LIBCCD;
  req.distance_tolerance = 1e-9;
  fcl::DistanceResultd res;
  fcl::CollisionObjectd a(shapes_->point, at), b(shapes_->geometry[obstacle], shapes_->pose[obstacle]);
  fcl::distance(&a, &b, req, res);
  const double d = res.min_distance + shapes_->point->radius;
  if (grad) {
    Eigen::Vector2d g;
    if (d > 0) {
      const Eigen::Vector3d n = Eigen::Vector3d(p[0], p[1], 0.0) - res.nearest_points[1];
      g = Eigen::Vector2d(n.x(), n.y());
      g = g.norm() > 0 ? g.normalized() : Eigen::Vector2d(1, 0);
    } else {
      edge_distance(poly, Eigen::Vector2d(p[0], p[1]), &g);
    }
    grad[0] = g.x();
    grad[1] = g.y();
  }
  return d;
}

}  // namespace marsyn::fcl_collision
