#pragma once
#include <cmath>

#include "marsyn/dynamics.hpp"
#include "marsyn/params.hpp"

namespace marsyn::models {

// Pendulum of paper Sec. 3.5: x1' = x2, x2' = -sin(x1) + gain * u (gain 1/5 in the paper),
// x1 the angle from hanging down [rad].
class Pendulum : public DynamicsModel<Pendulum> {
 public:
  explicit Pendulum(const Params& p = {}) : gain_(p.real("input_gain", 0.2)) {
    if (!(gain_ > 0)) throw ParamError("input_gain", "expected a positive number");
  }
  static std::vector<ParamSpec> param_specs() {
    return {{"input_gain", ParamType::Real, "0.2", "(0, inf)", "factor of the input in x2' (paper: 1/5)"}};
  }

  std::string type() const override { return "pendulum"; }
  int state_dim() const override { return 2; }
  int input_dim() const override { return 1; }
  std::vector<std::string> state_names() const override { return {"angle", "rate"}; }
  std::vector<std::string> input_names() const override { return {"torque"}; }
  std::vector<bool> periodic() const override { return {true, false}; }  // the angle

  template <class S>
  void vector_field(const S* x, const S* u, S* dx) const {
    using std::sin;
    dx[0] = x[1];
    dx[1] = gain_ * u[0] - sin(x[0]);
  }

 private:
  double gain_;
};

}  // namespace marsyn::models
