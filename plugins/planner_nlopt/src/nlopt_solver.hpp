#pragma once
// Single shooting over the inputs with NLopt: the states are a function of U through the RK4
// map, the objective and every requirement row are differentiated exactly (adjoint for the
// objective, forward sensitivities for the constraint rows, both from the AD Jacobians of the
// RK4 map). Dense in the number of inputs x requirement rows, hence for small problems.
#include <string>
#include <vector>

#include "marsyn/params.hpp"
#include "marsyn/planner.hpp"

namespace marsyn::nlopt_planner {

struct Options {
  std::string algorithm = "auglag_lbfgs";  // auglag_lbfgs | auglag_slsqp | slsqp | mma
  double r_input = 0.01;           // weight of 1/2 |u|^2
  double q_terminal = 1.0;         // weight of 1/2 |x_T - goal centre|^2
  double feasibility_tolerance = 1e-5;  // largest violation (buffered rows) accepted as exact
  double xtol_rel = 1e-8;
  double ftol_rel = 1e-10;
  long max_evaluations = 20000;
  double max_dense_entries = 2e7;  // rows x inputs of the dense constraint Jacobian; larger = refuse

  // The parameters, declared once in options.cpp (defaults: the initializers above).
  static std::vector<ParamSpec> specs();
  static Options from(const Params& p);  // throws ParamError
};

PlanResult solve(const PlanningProblem& problem, const PlanOptions& run, const Options& options);

}  // namespace marsyn::nlopt_planner
