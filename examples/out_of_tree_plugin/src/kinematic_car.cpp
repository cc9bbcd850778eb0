// A third-party dynamics model: a kinematic car steered by path curvature.
//   x' = v cos(theta), y' = v sin(theta), theta' = v * kappa, kappa = curvature input,
// with |kappa| limited by the config's input bounds. One template gives simulation, exact
// Jacobians and sound interval enclosures.
#include <marsyn/plugin.hpp>

#include <cmath>

namespace {

class KinematicCar : public marsyn::DynamicsModel<KinematicCar> {
 public:
  explicit KinematicCar(const marsyn::Params& p) : speed_scale_(p.real("speed_scale", 1.0)) {
    if (!(speed_scale_ > 0)) throw marsyn::ParamError("speed_scale", "expected a positive number");
  }
  static std::vector<marsyn::ParamSpec> param_specs() {
    return {{"speed_scale", marsyn::ParamType::Real, "1.0", "(0, inf)", "multiplies the speed input"}};
  }

  std::string type() const override { return "kinematic_car"; }
  int state_dim() const override { return 3; }
  int input_dim() const override { return 2; }
  std::vector<std::string> state_names() const override { return {"x", "y", "theta"}; }
  std::vector<std::string> input_names() const override { return {"v", "kappa"}; }
  std::vector<bool> field_independent_of() const override { return {true, true, false}; }

  template <class S>
  void vector_field(const S* x, const S* u, S* dx) const {
    using std::cos;
    using std::sin;
    const S v = speed_scale_ * u[0];
    dx[0] = v * cos(x[2]);
    dx[1] = v * sin(x[2]);
    dx[2] = v * u[1];
  }

 private:
  double speed_scale_;
};

}  // namespace

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::Dynamics, KinematicCar>(
    "kinematic_car", "kinematic car steered by curvature (out-of-tree example)"))
