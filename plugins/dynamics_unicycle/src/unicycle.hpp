#pragma once
#include "marsyn/dynamics.hpp"
#include "marsyn/params.hpp"

namespace marsyn::models {

// Unicycle (drones, lane-merging cars): x' = v cos(th), y' = v sin(th), th' = omega.
class Unicycle : public DynamicsModel<Unicycle> {
 public:
  explicit Unicycle(const Params& = {}) {}

  std::string type() const override { return "unicycle"; }
  int state_dim() const override { return 3; }
  int input_dim() const override { return 2; }
  std::vector<std::string> state_names() const override { return {"x", "y", "theta"}; }
  std::vector<std::string> input_names() const override { return {"v", "omega"}; }
  // Position never enters the field: successor boxes translate with the cell.
  std::vector<bool> field_independent_of() const override { return {true, true, false}; }

  template <class S>
  void vector_field(const S* x, const S* u, S* dx) const {
    using std::cos;
    using std::sin;
    dx[0] = u[0] * cos(x[2]);
    dx[1] = u[0] * sin(x[2]);
    dx[2] = u[1];
  }
};

}  // namespace marsyn::models
