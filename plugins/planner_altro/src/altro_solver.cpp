#include "altro_solver.hpp"

#include <exception>

#include "solver.hpp"

namespace marsyn::altro {

PlanResult solve(const PlanningProblem& pp, const PlanOptions& run, const Options& opt) {
  PlanResult bad;
  bad.status = PlannerStatus::InvalidInput;
  if (!pp.problem || pp.horizon <= 0 || pp.problem->agents.empty()) {
    bad.message = "no problem, no agents or a non-positive horizon";
    return bad;
  }
  const int n = pp.problem->product_state_dim(), m = pp.problem->product_input_dim();
  if (pp.x0.size() != n || pp.state_bounds.dim() != n || pp.goal.dim() != n || pp.input_bounds.dim() != m) {
    bad.message = "bounds, goal or x0 do not match the product dimensions";
    return bad;
  }
  if (!opt.q_state.empty() && static_cast<int>(opt.q_state.size()) != n) {
    bad.message = "q_state has " + std::to_string(opt.q_state.size()) + " entries, the product system " +
                  std::to_string(n) + " states";
    return bad;
  }
  for (const auto& a : pp.problem->agents)
    if (!a.dynamics || a.n() + a.m() > kMaxDual) {
      bad.message = "agent " + a.name + " has no dynamics or too many coordinates for the AD Jacobians";
      return bad;
    }
  try {
    return detail::Solver(pp, run, opt).run();
  } catch (const std::exception& e) {
    PlanResult r;
    r.status = PlannerStatus::Crash;
    r.message = e.what();
    return r;
  }
}

}  // namespace marsyn::altro
