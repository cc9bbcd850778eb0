// The planner's typed parameters, each declared once (marsyn/param_set.hpp): name, range and doc
// here, the default in Options (ipopt_solver.hpp); listing, parsing and checks read this one
// declaration.
#include "ipopt_solver.hpp"
#include "marsyn/param_set.hpp"

namespace marsyn::ipopt_planner {

namespace {

ParamSet<Options> declare() {
  using O = Options;
  // A negative weight is reported under r_input and a non-positive tolerance under tol, as they
  // always were.
  const Rule<double> weight{[](const double& w) { return !(w < 0); }, "weights must be non-negative"};
  const Rule<double> tolerance{[](const double& t) { return t > 0; }, "tolerances must be positive"};
  ParamSet<O> s;
  s.choice("hessian", &O::hessian, {"exact", "differenced", "limited-memory"},
           "Hessian of the Lagrangian: AD second derivatives where the interfaces provide them (other blocks "
           "differenced, see the result message), central differences of the exact AD Jacobians, or Ipopt's L-BFGS");
  s.add("r_input", &O::r_input, "[0, inf)", "weight of the input energy 1/2 |u|^2").require_last(weight, "r_input");
  s.add("q_terminal", &O::q_terminal, "[0, inf)", "weight of 1/2 |x_T - goal centre|^2").require_last(weight, "r_input");
  s.add("tol", &O::tol, "(0, 1)", "Ipopt tol").require_last(tolerance, "tol");
  s.add("constr_viol_tol", &O::constr_viol_tol, "(0, 1e-4)", "Ipopt constr_viol_tol (defects and rows)")
      .require_last(tolerance, "tol");
  s.add("feasibility_tolerance", &O::feasibility_tolerance, "(0, 1e-3)",
        "largest violation of the re-simulated plan reported as exact")
      .require_last(tolerance, "tol");
  s.add("max_iterations", &O::max_iterations, "[1, inf)", "Ipopt max_iter")
      .require_last({[](const int& v) { return !(v < 1); }, "must be at least 1"});
  s.add("bend", &O::bend, "[0, 1]", "lateral bend of the straight-line initial guess (x path length)");
  s.add("print_level", &O::print_level, "[0, 12]", "Ipopt print_level");
  s.add("linear_solver", &O::linear_solver, "mumps|ma27|...", "Ipopt linear_solver (Debian ships mumps)");
  s.choice("mu_strategy", &O::mu_strategy, {"adaptive", "monotone"}, "Ipopt barrier parameter strategy");
  s.add("fit_inputs", &O::fit_inputs, "true|false",
        "interpolate: start the inputs at a least-squares fit to the guessed states (else 0)");
  // Not checked here: passed to Ipopt as written.
  s.add("derivative_test", &O::derivative_test, "none|first-order|second-order",
        "Ipopt's finite-difference check of the derivatives at the initial point (printed)");
  s.add("output_file", &O::output_file, "path", "Ipopt output_file (its log, at least print level 5 there)");
  s.choice("initial_guess", &O::initial_guess, {"interpolate", "rollout"},
           "without a warm start: bent straight lines to the goal, or the states of zero inputs");
  return s;
}

}  // namespace

std::vector<ParamSpec> Options::specs() { return declared_once<declare>().specs(); }

Options Options::from(const Params& p) { return declared_once<declare>().parse(p); }

}  // namespace marsyn::ipopt_planner
