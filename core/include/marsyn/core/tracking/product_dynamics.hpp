#pragma once
// The product of all agents' dynamics as one Dynamics (paper Sec. 2: the agents are uncoupled,
// so the product field is the stacked fields). Used by the global ABCD baseline.
#include <memory>
#include <vector>

#include "marsyn/problem.hpp"

namespace marsyn {

class ProductDynamics final : public Dynamics {
 public:
  explicit ProductDynamics(const std::vector<AgentSpec>& agents);

  std::string type() const override { return type_; }
  int state_dim() const override { return n_; }
  int input_dim() const override { return m_; }
  std::vector<std::string> state_names() const override;
  std::vector<std::string> input_names() const override;
  std::vector<bool> field_independent_of() const override;

  void field(const double* x, const double* u, double* dx) const override { apply(x, u, dx); }
  void field(const DualD* x, const DualD* u, DualD* dx) const override { apply(x, u, dx); }
  void field(const Interval* x, const Interval* u, Interval* dx) const override { apply(x, u, dx); }
  void field(const DualI* x, const DualI* u, DualI* dx) const override { apply(x, u, dx); }

 private:
  template <class S>
  void apply(const S* x, const S* u, S* dx) const {
    for (std::size_t i = 0; i < parts_.size(); ++i) parts_[i]->field(x + xo_[i], u + uo_[i], dx + xo_[i]);
  }
  std::vector<std::shared_ptr<const Dynamics>> parts_;
  std::vector<std::string> names_;
  std::vector<int> xo_, uo_;
  int n_ = 0, m_ = 0;
  std::string type_;
};

}  // namespace marsyn
