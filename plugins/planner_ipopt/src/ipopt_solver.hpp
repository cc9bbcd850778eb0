#pragma once
// Direct multiple shooting with Ipopt: states x_1..x_T and inputs u_0..u_{T-1} are variables,
// the RK4 map enters as defect equalities x_{k+1} - f_tau(x_k, u_k) = 0, state/input bounds
// and the shrunk goal are variable bounds, and the eps-robust constraints are sparse
// inequalities. The constraint Jacobian is exact (AD Jacobians of the RK4 map and the
// constraints' own Jacobians). The Hessian of the Lagrangian is assembled block by block, from
// AD second derivatives where the interfaces provide them and central differences of the exact
// first derivatives elsewhere, or left to Ipopt's limited-memory approximation (second_order.hpp,
// docs/planners.md).
#include <string>
#include <vector>

#include "marsyn/params.hpp"
#include "marsyn/planner.hpp"
#include "second_order.hpp"

namespace marsyn::ipopt_planner {

struct Options {
  std::string hessian = "exact";  // exact | differenced | limited-memory
  double r_input = 0.01;
  double q_terminal = 0.0;            // the goal is a hard box; this only biases towards its centre
  double tol = 1e-6;                  // Ipopt tol
  double constr_viol_tol = 1e-8;      // Ipopt's own violation tolerance (defects, rows)
  double feasibility_tolerance = 1e-5;  // of the re-simulated plan, for reporting exact
  int max_iterations = 3000;
  double bend = 0.1;                  // lateral bend of the initial straight-line guess (x length)
  int print_level = 0;
  std::string linear_solver = "mumps";
  std::string mu_strategy = "adaptive";     // Ipopt mu_strategy: adaptive | monotone
  std::string initial_guess = "interpolate";  // interpolate | rollout (of the initial inputs)
  bool fit_inputs = true;                     // interpolate: inputs fitted to the guessed states
  std::string derivative_test = "none";       // Ipopt derivative_test: none | first-order | second-order
  std::string output_file;                    // Ipopt output_file (empty: none)

  // The parameters, declared once in options.cpp (defaults: the initializers above).
  static std::vector<ParamSpec> specs();
  static Options from(const Params& p);  // throws ParamError
};

// `fields` (per agent, optional): vector fields with nested duals for the exact dynamics blocks,
// for callers that hold the concrete models; by default whatever marsyn::Dynamics offers.
PlanResult solve(const PlanningProblem& problem, const PlanOptions& run, const Options& options,
                 std::vector<SecondOrderField> fields = {});

}  // namespace marsyn::ipopt_planner
