#pragma once
#include <cmath>

#include "marsyn/dynamics.hpp"
#include "marsyn/params.hpp"

namespace marsyn::models {

// Cart-pole (the crane): state (z, z', theta, theta'), input force F on the cart. theta = pi is
// the pendulum hanging down. Equations of the case studies (Barto et al.), g > 0:
//   theta'' = (g sin th - cos th (F + mp l th'^2 sin th) / mt) / (l (4/3 - mp cos^2 th / mt))
//   z''     = (F + mp l th'^2 sin th) / mt - mp l theta'' cos th / mt
class CartPole : public DynamicsModel<CartPole> {
 public:
  explicit CartPole(const Params& p = {})
      : g_(p.real("gravity", 9.8)),
        mc_(p.real("cart_mass", 1.0)),
        mp_(p.real("pole_mass", 0.1)),
        l_(p.real("half_pole_length", 0.5)),
        tip_(p.real("tip_length", 0.5)),
        rail_(p.real("rail_height", 0.6)) {
    if (!(g_ > 0)) throw ParamError("gravity", "expected a positive number");
    if (!(mc_ > 0)) throw ParamError("cart_mass", "expected a positive number");
    if (!(mp_ > 0)) throw ParamError("pole_mass", "expected a positive number");
    if (!(l_ > 0)) throw ParamError("half_pole_length", "expected a positive number");
    if (!(tip_ >= 0)) throw ParamError("tip_length", "expected a non-negative number");
  }

  static std::vector<ParamSpec> param_specs() {
    return {{"gravity", ParamType::Real, "9.8", "(0, inf)", "gravitational acceleration [m/s^2]"},
            {"cart_mass", ParamType::Real, "1.0", "(0, inf)", "cart (trolley) mass [kg]"},
            {"pole_mass", ParamType::Real, "0.1", "(0, inf)", "pole mass [kg]"},
            {"half_pole_length", ParamType::Real, "0.5", "(0, inf)", "half the pole length l [m]"},
            {"tip_length", ParamType::Real, "0.5", "[0, inf)", "rail-to-tip length of the footprint [m]"},
            {"rail_height", ParamType::Real, "0.6", "(-inf, inf)", "height of the rail in the workspace [m]"}};
  }

  std::string type() const override { return "cartpole"; }
  int state_dim() const override { return 4; }
  int input_dim() const override { return 1; }
  std::vector<std::string> state_names() const override { return {"z", "z_dot", "theta", "theta_dot"}; }
  std::vector<std::string> input_names() const override { return {"force"}; }
  std::vector<bool> field_independent_of() const override { return {true, false, false, false}; }
  // The pole angle (the tip footprint reads it through sin and cos too).
  std::vector<bool> periodic() const override { return {false, false, true, false}; }
  std::vector<std::string> footprints() const override { return {"pendulum_tip"}; }

  template <class S>
  void vector_field(const S* x, const S* u, S* dx) const {
    using std::cos;
    using std::sin;
    const double mt = mc_ + mp_;
    const S s = sin(x[2]), c = cos(x[2]);
    const S push = (u[0] + mp_ * l_ * (x[3] * x[3]) * s) / mt;
    const S th_dd = (g_ * s - c * push) / (l_ * (4.0 / 3.0 - (mp_ / mt) * (c * c)));
    dx[0] = x[1];
    dx[1] = push - (mp_ * l_ / mt) * th_dd * c;
    dx[2] = x[3];
    dx[3] = th_dd;
  }

  // The pendulum tip in the workspace plane: (z + tip sin th, rail + tip cos th).
  template <class S>
  void footprint_point(int, const S* x, S* p) const {
    using std::cos;
    using std::sin;
    p[0] = x[0] + tip_ * sin(x[2]);
    p[1] = rail_ + tip_ * cos(x[2]);
  }

 private:
  double g_, mc_, mp_, l_, tip_, rail_;
};

}  // namespace marsyn::models
