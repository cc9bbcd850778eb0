#include "ipopt_solver.hpp"

#include <IpIpoptApplication.hpp>
#include <algorithm>
#include <mutex>
#include <sstream>

#include "marsyn/planner_support/clock.hpp"
#include "shooting_nlp.hpp"

namespace marsyn::ipopt_planner {

std::vector<ParamSpec> Options::specs() {
  return {
      {"hessian", ParamType::String, "exact", "exact|differenced|limited-memory",
       "Hessian of the Lagrangian: AD second derivatives where the interfaces provide them (other blocks "
       "differenced, see the result message), central differences of the exact AD Jacobians, or Ipopt's L-BFGS"},
      {"r_input", ParamType::Real, "0.01", "[0, inf)", "weight of the input energy 1/2 |u|^2"},
      {"q_terminal", ParamType::Real, "0", "[0, inf)", "weight of 1/2 |x_T - goal centre|^2"},
      {"tol", ParamType::Real, "1e-6", "(0, 1)", "Ipopt tol"},
      {"constr_viol_tol", ParamType::Real, "1e-8", "(0, 1e-4)", "Ipopt constr_viol_tol (defects and rows)"},
      {"feasibility_tolerance", ParamType::Real, "1e-5", "(0, 1e-3)",
       "largest violation of the re-simulated plan reported as exact"},
      {"max_iterations", ParamType::Int, "3000", "[1, inf)", "Ipopt max_iter"},
      {"bend", ParamType::Real, "0.1", "[0, 1]", "lateral bend of the straight-line initial guess (x path length)"},
      {"print_level", ParamType::Int, "0", "[0, 12]", "Ipopt print_level"},
      {"linear_solver", ParamType::String, "mumps", "mumps|ma27|...", "Ipopt linear_solver (Debian ships mumps)"},
      {"mu_strategy", ParamType::String, "adaptive", "adaptive|monotone", "Ipopt barrier parameter strategy"},
      {"fit_inputs", ParamType::Bool, "true", "true|false",
       "interpolate: start the inputs at a least-squares fit to the guessed states (else 0)"},
      {"derivative_test", ParamType::String, "none", "none|first-order|second-order",
       "Ipopt's finite-difference check of the derivatives at the initial point (printed)"},
      {"output_file", ParamType::String, "", "path", "Ipopt output_file (its log, at least print level 5 there)"},
      {"initial_guess", ParamType::String, "interpolate", "interpolate|rollout",
       "without a warm start: bent straight lines to the goal, or the states of zero inputs"},
  };
}

Options Options::from(const Params& p) {
  Options o;
  o.hessian = p.text("hessian", o.hessian);
  if (o.hessian != "exact" && o.hessian != "differenced" && o.hessian != "limited-memory")
    throw ParamError("hessian", "expected exact, differenced or limited-memory");
  o.r_input = p.real("r_input", o.r_input);
  o.q_terminal = p.real("q_terminal", o.q_terminal);
  o.tol = p.real("tol", o.tol);
  o.constr_viol_tol = p.real("constr_viol_tol", o.constr_viol_tol);
  o.feasibility_tolerance = p.real("feasibility_tolerance", o.feasibility_tolerance);
  o.max_iterations = static_cast<int>(p.integer("max_iterations", o.max_iterations));
  o.bend = p.real("bend", o.bend);
  o.print_level = static_cast<int>(p.integer("print_level", o.print_level));
  o.linear_solver = p.text("linear_solver", o.linear_solver);
  o.mu_strategy = p.text("mu_strategy", o.mu_strategy);
  if (o.mu_strategy != "adaptive" && o.mu_strategy != "monotone") throw ParamError("mu_strategy", "expected adaptive or monotone");
  o.fit_inputs = p.boolean("fit_inputs", o.fit_inputs);
  o.derivative_test = p.text("derivative_test", o.derivative_test);
  o.output_file = p.text("output_file", o.output_file);
  o.initial_guess = p.text("initial_guess", o.initial_guess);
  if (o.initial_guess != "interpolate" && o.initial_guess != "rollout")
    throw ParamError("initial_guess", "expected interpolate or rollout");
  if (o.r_input < 0 || o.q_terminal < 0) throw ParamError("r_input", "weights must be non-negative");
  if (!(o.tol > 0) || !(o.constr_viol_tol > 0) || !(o.feasibility_tolerance > 0))
    throw ParamError("tol", "tolerances must be positive");
  if (o.max_iterations < 1) throw ParamError("max_iterations", "must be at least 1");
  return o;
}

namespace {
// Debian's Ipopt 3.11 solves with sequential MUMPS, which keeps global state: two solves at once
// in one process crash. Every solve in this library takes this lock.
std::mutex& ipopt_mutex() {
  static std::mutex m;
  return m;
}
}  // namespace

PlanResult solve(const PlanningProblem& pp, const PlanOptions& run, const Options& o,
                 std::vector<SecondOrderField> fields) {
  const double t0 = planner_support::now_seconds();
  PlanResult res;
  if (!pp.problem || pp.horizon <= 0) {
    res.status = PlannerStatus::InvalidInput;
    res.message = "no problem or a non-positive horizon";
    return res;
  }
  planner_support::ProductModel model(pp);
  Ipopt::SmartPtr<ShootingNlp> nlp = new ShootingNlp(model, o, run, t0, std::move(fields));
  Ipopt::ApplicationReturnStatus st;
  int iterations = 0;
  {
    std::lock_guard<std::mutex> lock(ipopt_mutex());
    Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
    app->Options()->SetIntegerValue("print_level", o.print_level);
    app->Options()->SetStringValue("sb", "yes");
    app->Options()->SetNumericValue("tol", o.tol);
    app->Options()->SetNumericValue("constr_viol_tol", o.constr_viol_tol);
    app->Options()->SetIntegerValue("max_iter", o.max_iterations);
    app->Options()->SetStringValue("mu_strategy", o.mu_strategy);
    app->Options()->SetStringValue("linear_solver", o.linear_solver);
    app->Options()->SetStringValue("hessian_approximation",
                                   o.hessian == "limited-memory" ? "limited-memory" : "exact");
    if (o.derivative_test != "none") {
      app->Options()->SetStringValue("derivative_test", o.derivative_test);
      app->Options()->SetNumericValue("derivative_test_tol", 1e-4);
      // The checker's findings are printed: on the console unless they go to output_file.
      if (o.output_file.empty()) app->Options()->SetIntegerValue("print_level", std::max(o.print_level, 4));
    }
    if (!o.output_file.empty()) {
      app->Options()->SetStringValue("output_file", o.output_file);
      app->Options()->SetIntegerValue("file_print_level", std::max(o.print_level, 5));
    }
    if (pp.warm_start) app->Options()->SetNumericValue("bound_push", 1e-6);
    st = app->Initialize();
    if (st != Ipopt::Solve_Succeeded) {
      res.status = PlannerStatus::Crash;
      res.message = "Ipopt failed to initialize";
      return res;
    }
    try {
      st = app->OptimizeTNLP(nlp);
    } catch (const std::exception& e) {
      res.status = PlannerStatus::Crash;
      res.message = std::string("Ipopt threw: ") + e.what();
      return res;
    }
    iterations = nlp->iterations();
  }
  res.iterations = iterations;
  res.solve_time_s = planner_support::now_seconds() - t0;
  if (nlp->inputs().empty()) {
    res.status = PlannerStatus::Crash;
    res.message = "Ipopt returned no solution (status " + std::to_string(static_cast<int>(st)) + ")";
    return res;
  }
  // The plan is the inputs alone, re-simulated: defects Ipopt left within its tolerance are
  // measured here, in the same terms as the exact check.
  std::vector<Eigen::VectorXd> U = nlp->inputs();
  for (auto& u : U)
    for (int j = 0; j < model.m; ++j) u[j] = std::clamp(u[j], pp.input_bounds.lo[j], pp.input_bounds.hi[j]);
  res.plan.tau = model.tau;
  res.plan.u = U;
  res.plan.x = model.rollout(U);
  std::string worst;
  res.max_violation = model.violation(res.plan.x, U, &worst);
  res.cost = 0.5 * o.q_terminal * (res.plan.x.back() - model.goal_centre).squaredNorm();
  for (const auto& u : U) res.cost += 0.5 * o.r_input * u.squaredNorm();
  const bool converged = st == Ipopt::Solve_Succeeded || st == Ipopt::Solved_To_Acceptable_Level;
  std::ostringstream os;
  os << "ipopt status " << static_cast<int>(st) << " (" << o.hessian << " Hessian";
  if (o.hessian == "exact") {
    // Blocks the interfaces cannot differentiate twice are differenced; say which.
    const auto& b = nlp->hessian_blocks();
    if (b.dynamics_differenced > 0)
      os << "; dynamics blocks differenced: " << (interface_has_second_order_field() ? "no DualD2 field" : "marsyn::Dynamics has no DualD2 field");
    if (b.constraints_differenced > 0)
      os << "; constraint blocks differenced: "
         << (interface_has_constraint_hessian() ? "no hessian()" : "marsyn::Constraint has no hessian()");
  }
  os << ")";
  if (nlp->hessian_evaluations() > 0)
    os << ", " << nlp->hessian_evaluations() << " Hessians in " << nlp->hessian_seconds() << " s";
  if (converged && res.max_violation <= o.feasibility_tolerance) {
    res.status = PlannerStatus::ExactSolution;
  } else if (nlp->timed_out()) {
    res.status = PlannerStatus::Timeout;
  } else if (st == Ipopt::Infeasible_Problem_Detected) {
    res.status = PlannerStatus::Infeasible;
  } else {
    res.status = PlannerStatus::ApproximateSolution;
  }
  if (res.status != PlannerStatus::ExactSolution) os << "; worst: " << worst << " (" << res.max_violation << ")";
  res.message = os.str();
  return res;
}

}  // namespace marsyn::ipopt_planner
