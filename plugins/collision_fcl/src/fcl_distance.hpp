#pragma once
// Signed Euclidean distance from a workspace point to planar obstacles, computed by FCL: each
// obstacle (an axis-aligned box or a convex polygon) is a 3-D shape extruded along z, the point
// is a sphere of radius 0 in its mid-plane. The extrusion is tall enough that the nearest
// boundary is always a side face, so the 3-D distance is the planar one.
//
// On overlap (point inside) the value is minus the penetration depth, i.e. minus the distance
// to the nearest edge, and the gradient is the outward normal of that edge: the same convention
// as core's exact planar geometry, so either provider can stand behind a constraint.
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "marsyn/constraint.hpp"
#include "marsyn/params.hpp"
#include "marsyn/problem.hpp"

namespace marsyn::fcl_collision {

class FclDistance final : public DistanceModel {
 public:
  // Params: `boxes` = [lo_x, lo_y, hi_x, hi_y]*; `polygons` = [k, x_1, y_1, ..., x_k, y_k]*
  // (convex, counter-clockwise). Boxes come first in the obstacle numbering.
  explicit FclDistance(const Params& params);
  explicit FclDistance(const std::vector<Obstacle>& obstacles);
  ~FclDistance() override;
  static std::vector<ParamSpec> param_specs();
  // The params that describe these obstacles (for configs and the registry).
  static Params params_for(const std::vector<Obstacle>& obstacles);

  int obstacles() const;
  double distance(int obstacle, const double* p, double* grad) const override;

 private:
  struct Shapes;
  void add_polygon(std::vector<Eigen::Vector2d> vertices, bool is_box);
  std::unique_ptr<Shapes> shapes_;
};

}  // namespace marsyn::fcl_collision
