#include "marsyn/core/planning/projector.hpp"

#include <stdexcept>

#include "marsyn/core/planning/constraints.hpp"

namespace marsyn::planning {

std::vector<NominalTrajectory> ProductProjector::project(const Problem& problem, const GlobalPlan& plan) const {
  const ProductLayout at(problem);
  const auto &xo = at.state, &uo = at.input;
  if (plan.x.size() != plan.u.size() + 1)
    throw std::invalid_argument("marsyn::planning::ProductProjector: plan needs T+1 states for T inputs");
  std::vector<NominalTrajectory> out;
  for (size_t i = 0; i < problem.agents.size(); ++i) {
    const auto& a = problem.agents[i];
    NominalTrajectory tr;
    tr.agent = a.name;
    for (const auto& x : plan.x) tr.x.push_back(x.segment(xo[i], a.n()));
    for (const auto& u : plan.u) tr.u.push_back(u.segment(uo[i], a.m()));
    out.push_back(std::move(tr));
  }
  return out;
}

}  // namespace marsyn::planning
