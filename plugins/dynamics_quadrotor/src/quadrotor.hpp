#pragma once
#include <cmath>

#include "marsyn/dynamics.hpp"
#include "marsyn/params.hpp"

namespace marsyn::models {

// Rigid-body quadrotor, 12 states: position (x, y, z) in a world frame with z up, ZYX Euler
// angles (roll phi, pitch theta, yaw psi; body-to-world rotation R = Rz(psi) Ry(theta) Rx(phi)),
// world-frame velocity (vx, vy, vz), body angular rates (p, q, r). Inputs: T the collective
// thrust per mass along the body z axis [m/s^2], and the body torques per principal inertia
// (tau_x / Ixx, tau_y / Iyy, tau_z / Izz) [rad/s^2]:
//   x' = vx, y' = vy, z' = vz
//   phi'   = p + (q sin phi + r cos phi) sin theta / cos theta
//   theta' = q cos phi - r sin phi
//   psi'   = (q sin phi + r cos phi) / cos theta
//   vx' = T (cos phi sin theta cos psi + sin phi sin psi)
//   vy' = T (cos phi sin theta sin psi - sin phi cos psi)
//   vz' = T cos phi cos theta - g
//   p' = (Iyy - Izz) / Ixx q r + u1,  q' = (Izz - Ixx) / Iyy p r + u2,  r' = (Ixx - Iyy) / Izz p q + u3
// The Euler-angle kinematics are singular at theta = +-pi/2 (gimbal lock): state bounds must
// keep |theta| well below pi/2. tan(theta) is written as sin/cos, the same enclosure for an
// interval of one sign, using FastInterval's own sin and cos in the tracker's hot path.
class Quadrotor : public DynamicsModel<Quadrotor> {
 public:
  explicit Quadrotor(const Params& p = {})
      : g_(p.real("gravity", 9.81)),
        ixx_(p.real("inertia_xx", 1.657e-5)),
        iyy_(p.real("inertia_yy", 1.666e-5)),
        izz_(p.real("inertia_zz", 2.926e-5)) {
    if (!(g_ > 0) || !std::isfinite(g_)) throw ParamError("gravity", "expected a positive number");
    if (!(ixx_ > 0) || !std::isfinite(ixx_)) throw ParamError("inertia_xx", "expected a positive number");
    if (!(iyy_ > 0) || !std::isfinite(iyy_)) throw ParamError("inertia_yy", "expected a positive number");
    if (!(izz_ > 0) || !std::isfinite(izz_)) throw ParamError("inertia_zz", "expected a positive number");
    // Principal moments of a rigid body satisfy the triangle inequalities.
    if (!(ixx_ <= iyy_ + izz_)) throw ParamError("inertia_xx", "expected inertia_xx <= inertia_yy + inertia_zz");
    if (!(iyy_ <= ixx_ + izz_)) throw ParamError("inertia_yy", "expected inertia_yy <= inertia_xx + inertia_zz");
    if (!(izz_ <= ixx_ + iyy_)) throw ParamError("inertia_zz", "expected inertia_zz <= inertia_xx + inertia_yy");
    kp_ = (iyy_ - izz_) / ixx_;
    kq_ = (izz_ - ixx_) / iyy_;
    kr_ = (ixx_ - iyy_) / izz_;
  }

  static std::vector<ParamSpec> param_specs() {
    // Defaults: the Crazyflie 2.0 (Foerster 2015). Only the ratios enter the field.
    return {{"gravity", ParamType::Real, "9.81", "(0, inf)", "gravitational acceleration g [m/s^2]"},
            {"inertia_xx", ParamType::Real, "1.657e-5", "(0, inf)",
             "principal moment of inertia about body x [kg m^2] (only ratios matter; triangle inequality)"},
            {"inertia_yy", ParamType::Real, "1.666e-5", "(0, inf)", "principal moment of inertia about body y [kg m^2]"},
            {"inertia_zz", ParamType::Real, "2.926e-5", "(0, inf)", "principal moment of inertia about body z [kg m^2]"}};
  }

  std::string type() const override { return "quadrotor"; }
  int state_dim() const override { return 12; }
  int input_dim() const override { return 4; }
  std::vector<std::string> state_names() const override {
    return {"x", "y", "z", "phi", "theta", "psi", "vx", "vy", "vz", "p", "q", "r"};
  }
  std::vector<std::string> input_names() const override { return {"thrust", "torque_x", "torque_y", "torque_z"}; }
  // Position never enters the field: successor boxes translate with the cell.
  std::vector<bool> field_independent_of() const override {
    return {true, true, true, false, false, false, false, false, false, false, false, false};
  }
  // The yaw: roll and pitch enter through sin and cos too, but the Euler kinematics are singular
  // at theta = +-pi/2, so only psi turns freely.
  std::vector<bool> periodic() const override {
    return {false, false, false, false, false, true, false, false, false, false, false, false};
  }

  template <class S>
  void vector_field(const S* x, const S* u, S* dx) const {
    using std::cos;
    using std::sin;
    const S sphi = sin(x[3]), cphi = cos(x[3]);
    const S sth = sin(x[4]), cth = cos(x[4]);
    const S spsi = sin(x[5]), cpsi = cos(x[5]);
    const S& p = x[9];
    const S& q = x[10];
    const S& r = x[11];
    const S qr = q * sphi + r * cphi;
    dx[0] = x[6];
    dx[1] = x[7];
    dx[2] = x[8];
    dx[3] = p + qr * sth / cth;
    dx[4] = q * cphi - r * sphi;
    dx[5] = qr / cth;
    const S tilt = cphi * sth;
    dx[6] = u[0] * (tilt * cpsi + sphi * spsi);
    dx[7] = u[0] * (tilt * spsi - sphi * cpsi);
    dx[8] = u[0] * (cphi * cth) - g_;
    dx[9] = kp_ * (q * r) + u[1];
    dx[10] = kq_ * (p * r) + u[2];
    dx[11] = kr_ * (p * q) + u[3];
  }

  double gravity() const { return g_; }
  double inertia(int axis) const { return axis == 0 ? ixx_ : axis == 1 ? iyy_ : izz_; }

 private:
  double g_, ixx_, iyy_, izz_;
  double kp_ = 0, kq_ = 0, kr_ = 0;  // Euler's equations: (Iyy - Izz) / Ixx, ...
};

}  // namespace marsyn::models
