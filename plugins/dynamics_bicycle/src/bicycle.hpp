#pragma once
#include <cmath>

#include "marsyn/dynamics.hpp"
#include "marsyn/params.hpp"

namespace marsyn::models {

// Kinematic bicycle (rear-axle reference point) with speed and steering angle as states:
//   x' = v cos(theta), y' = v sin(theta), theta' = v tan(delta) / L, v' = a, delta' = delta_rate
// State (x, y, theta, v, delta), input (a, delta_rate), L the wheelbase. tan(delta) is finite for
// |delta| < pi/2; state bounds should keep the steering angle well inside that (an interval
// enclosure over a box reaching pi/2 is unbounded, which is sound but useless).
class Bicycle : public DynamicsModel<Bicycle> {
 public:
  explicit Bicycle(const Params& p = {}) : wheelbase_(p.real("wheelbase", 0.5)) {
    if (!(wheelbase_ > 0) || !std::isfinite(wheelbase_)) throw ParamError("wheelbase", "expected a positive number");
  }

  static std::vector<ParamSpec> param_specs() {
    return {{"wheelbase", ParamType::Real, "0.5", "(0, inf)", "distance L between the axles [m]"}};
  }

  std::string type() const override { return "bicycle"; }
  int state_dim() const override { return 5; }
  int input_dim() const override { return 2; }
  std::vector<std::string> state_names() const override { return {"x", "y", "theta", "v", "delta"}; }
  std::vector<std::string> input_names() const override { return {"accel", "steer_rate"}; }
  // Position never enters the field: successor boxes translate with the cell.
  std::vector<bool> field_independent_of() const override { return {true, true, false, false, false}; }
  std::vector<bool> periodic() const override { return {false, false, true, false, false}; }  // the heading

  template <class S>
  void vector_field(const S* x, const S* u, S* dx) const {
    using std::cos;
    using std::sin;
    using std::tan;
    const S c = cos(x[2]), s = sin(x[2]);  // before any store to dx, which may alias x: one sincos
    dx[0] = x[3] * c;
    dx[1] = x[3] * s;
    dx[2] = x[3] * tan(x[4]) / wheelbase_;
    dx[3] = u[0];
    dx[4] = u[1];
  }

  double wheelbase() const { return wheelbase_; }

 private:
  double wheelbase_;
};

}  // namespace marsyn::models
