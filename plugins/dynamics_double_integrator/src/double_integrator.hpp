#pragma once
#include "marsyn/dynamics.hpp"
#include "marsyn/params.hpp"

namespace marsyn::models {

// Double integrator (the vehicle): state (p, v), input acceleration a: p' = v, v' = a.
class DoubleIntegrator : public DynamicsModel<DoubleIntegrator> {
 public:
  explicit DoubleIntegrator(const Params& = {}) {}

  std::string type() const override { return "double_integrator"; }
  int state_dim() const override { return 2; }
  int input_dim() const override { return 1; }
  std::vector<std::string> state_names() const override { return {"p", "v"}; }
  std::vector<std::string> input_names() const override { return {"a"}; }
  std::vector<bool> field_independent_of() const override { return {true, false}; }

  template <class S>
  void vector_field(const S* x, const S* u, S* dx) const {
    dx[0] = x[1];
    dx[1] = u[0];
  }
};

}  // namespace marsyn::models
