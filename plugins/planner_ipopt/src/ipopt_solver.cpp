#include "ipopt_solver.hpp"

#include <IpIpoptApplication.hpp>
#include <algorithm>
#include <mutex>
#include <sstream>

#include "marsyn/planner_support/invalid_input.hpp"
#include "marsyn/stopwatch.hpp"
#include "marsyn/number_text.hpp"
#include "shooting_nlp.hpp"

namespace marsyn::ipopt_planner {

namespace {

// Ipopt's return status in its manual's words (a user reads "converged to a point of local
// infeasibility", not "status 2"); the number stays beside an unknown one (docs/messages.md).
std::string status_words(Ipopt::ApplicationReturnStatus st) {
  switch (st) {
    case Ipopt::Solve_Succeeded: return "solved";
    case Ipopt::Solved_To_Acceptable_Level: return "solved to an acceptable level";
    case Ipopt::Infeasible_Problem_Detected: return "converged to a point of local infeasibility";
    case Ipopt::Search_Direction_Becomes_Too_Small: return "the search direction became too small";
    case Ipopt::Diverging_Iterates: return "the iterates diverged";
    case Ipopt::User_Requested_Stop: return "stopped on request";
    case Ipopt::Feasible_Point_Found: return "a feasible point found";
    case Ipopt::Maximum_Iterations_Exceeded: return "the iteration limit was reached";
    case Ipopt::Restoration_Failed: return "the restoration phase failed";
    case Ipopt::Error_In_Step_Computation: return "an error in the step computation";
    case Ipopt::Maximum_CpuTime_Exceeded: return "the CPU time limit was reached";
    case Ipopt::Not_Enough_Degrees_Of_Freedom: return "not enough degrees of freedom";
    case Ipopt::Invalid_Problem_Definition: return "an invalid problem definition";
    case Ipopt::Invalid_Option: return "an invalid option";
    case Ipopt::Invalid_Number_Detected: return "an invalid number (NaN or Inf) in a function or derivative";
    default: break;
  }
  return "an outcome its manual does not list (" + std::to_string(static_cast<int>(st)) + ")";
}

// Debian's Ipopt 3.11 solves with sequential MUMPS, which keeps global state: two solves at once
// in one process crash. Every solve in this library takes this lock.
std::mutex& ipopt_mutex() {
  static std::mutex m;
  return m;
}
}  // namespace

PlanResult solve(const PlanningProblem& pp, const PlanOptions& run, const Options& o,
                 std::vector<SecondOrderField> fields) {
  const Stopwatch clock;
  if (auto refused = planner_support::invalid_input(pp)) return *refused;
  PlanResult res;
  planner_support::ProductModel model(pp);
  Ipopt::SmartPtr<ShootingNlp> nlp = new ShootingNlp(model, o, run, clock, std::move(fields));
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
  res.solve_time_s = clock.seconds();
  if (nlp->inputs().empty()) {
    res.status = PlannerStatus::Crash;
    res.message = "Ipopt returned no solution (" + status_words(st) + ")";
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
  os.precision(kMessageDigits);
  os << "Ipopt: " << status_words(st) << " (" << o.hessian << " Hessian";
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
