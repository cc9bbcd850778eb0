#pragma once
#include <cmath>

#include "marsyn/dynamics.hpp"
#include "marsyn/params.hpp"

namespace marsyn::models {

// Planar (2D) quadrotor in the vertical x-z plane, z up, pitch phi positive counterclockwise
// (tilting the thrust toward -x):
//   x' = vx, z' = vz, phi' = omega, vx' = -T sin(phi), vz' = T cos(phi) - g, omega' = tau
// State (x, z, phi, vx, vz, omega), input (T, tau): T the collective thrust per mass [m/s^2],
// tau the torque per moment of inertia [rad/s^2]. Hover: phi = 0, T = g.
class PlanarQuadrotor : public DynamicsModel<PlanarQuadrotor> {
 public:
  explicit PlanarQuadrotor(const Params& p = {}) : g_(p.real("gravity", 9.81)) {
    if (!(g_ > 0) || !std::isfinite(g_)) throw ParamError("gravity", "expected a positive number");
  }

  static std::vector<ParamSpec> param_specs() {
    return {{"gravity", ParamType::Real, "9.81", "(0, inf)", "gravitational acceleration g [m/s^2]"}};
  }

  std::string type() const override { return "planar_quadrotor"; }
  int state_dim() const override { return 6; }
  int input_dim() const override { return 2; }
  std::vector<std::string> state_names() const override { return {"x", "z", "phi", "vx", "vz", "omega"}; }
  std::vector<std::string> input_names() const override { return {"thrust", "torque"}; }
  // Position never enters the field: successor boxes translate with the cell.
  std::vector<bool> field_independent_of() const override { return {true, true, false, false, false, false}; }
  std::vector<bool> periodic() const override { return {false, false, true, false, false, false}; }  // the tilt phi

  template <class S>
  void vector_field(const S* x, const S* u, S* dx) const {
    using std::cos;
    using std::sin;
    dx[0] = x[3];
    dx[1] = x[4];
    dx[2] = x[5];
    const S s = sin(x[2]), c = cos(x[2]);  // before any store to dx, which may alias x: one sincos
    dx[3] = -(u[0] * s);
    dx[4] = u[0] * c - g_;
    dx[5] = u[1];
  }

  double gravity() const { return g_; }

 private:
  double g_;
};

}  // namespace marsyn::models
