#include "marsyn/core/tracking/product_dynamics.hpp"

namespace marsyn {

ProductDynamics::ProductDynamics(const std::vector<AgentSpec>& agents) {
  type_ = "product(";
  // Offsets from the models' own dimensions, not ProductLayout's (x0, input bounds): a product of
  // Dynamics is a model, and needs no agent data to be one.
  for (const auto& a : agents) {
    parts_.push_back(a.dynamics);
    names_.push_back(a.name);
    xo_.push_back(n_);
    uo_.push_back(m_);
    n_ += a.dynamics->state_dim();
    m_ += a.dynamics->input_dim();
    type_ += (type_.size() > 8 ? "," : "") + a.dynamics->type();
  }
  type_ += ")";
}

std::vector<std::string> ProductDynamics::state_names() const {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < parts_.size(); ++i)
    for (const auto& s : parts_[i]->state_names()) out.push_back(names_[i] + "." + s);
  return out;
}

std::vector<std::string> ProductDynamics::input_names() const {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < parts_.size(); ++i)
    for (const auto& s : parts_[i]->input_names()) out.push_back(names_[i] + "." + s);
  return out;
}

std::vector<bool> ProductDynamics::field_independent_of() const {
  std::vector<bool> out;
  for (const auto& p : parts_)
    for (bool b : p->field_independent_of()) out.push_back(b);
  return out;
}

}  // namespace marsyn
