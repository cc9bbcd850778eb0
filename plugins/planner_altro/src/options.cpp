// The solver's typed parameters, each declared once (marsyn/param_set.hpp): name, range and doc
// here, the default in Options (altro_solver.hpp); listing, parsing and range checks all read
// this one declaration.
#include <cmath>
#include <string>

#include "altro_solver.hpp"
#include "marsyn/param_set.hpp"

namespace marsyn::altro {

namespace {

// The lower bounds, worded as the loader's users have always read them ("expected an integer
// >= 1", "expected a number > 0.000000").
Rule<int> integer_at_least(long lo) {
  return {[lo](const int& v) { return v >= lo; }, "expected an integer >= " + std::to_string(lo)};
}
Rule<double> number_above(double lo) {
  return {[lo](const double& v) { return v > lo; }, "expected a number > " + std::to_string(lo)};
}
Rule<double> number_at_least(double lo) {
  return {[lo](const double& v) { return v >= lo; }, "expected a number >= " + std::to_string(lo)};
}

ParamSet<Options> declare() {
  using O = Options;
  // Stream: the listing has always written these defaults as std::ostream does ("1e-05").
  ParamSet<O> s(NumberText::Stream);
  s.add("max_iterations", &O::max_iterations, "[1, inf)", "iLQR iterations in total").require(integer_at_least(1));
  s.add("max_outer", &O::max_outer, "[1, inf)", "augmented-Lagrangian (multiplier) updates").require(integer_at_least(1));
  s.add("max_inner", &O::max_inner, "[1, inf)", "iLQR iterations per multiplier update").require(integer_at_least(1));
  s.add("cost_tolerance", &O::cost_tolerance, "(0, inf)", "relative cost decrease ending an inner solve near feasibility")
      .require(number_above(0));
  s.add("cost_tolerance_intermediate", &O::cost_tolerance_intermediate, "(0, inf)",
        "relative cost decrease ending an inner solve while infeasible")
      .require(number_above(0));
  s.add("constraint_tolerance", &O::constraint_tolerance, "(0, inf)", "largest constraint violation accepted as converged")
      .require(number_above(0));
  s.add("penalty_initial", &O::penalty_initial, "(0, inf)", "initial penalty rho").require(number_above(0));
  s.add("penalty_scaling", &O::penalty_scaling, "(1, inf)", "rho factor per outer update").require(number_above(1));
  s.add("penalty_max", &O::penalty_max, "(0, inf)", "largest penalty").require(number_above(0));
  s.add("reg_initial", &O::reg_initial, "[0, inf)", "initial regularization of Quu").require(number_at_least(0));
  s.add("reg_min", &O::reg_min, "[0, inf)", "smallest regularization").require(number_at_least(0));
  s.add("reg_max", &O::reg_max, "(0, inf)", "largest regularization (beyond: stalled)").require(number_above(0));
  s.add("reg_factor", &O::reg_factor, "(1, inf)", "regularization change factor").require(number_above(1));
  // The upper end is reported after every other parameter's rule, as it always was.
  s.add("small_step", &O::small_step, "(0, 1]", "accepted steps this short raise regularization")
      .require(number_above(0))
      .require_last({[](const double& v) { return !(v > 1); }, "expected a number in (0, 1]"});
  // The loader enforces the upper end of integer ranges; the solver needs only >= 1.
  s.add("line_search_steps", &O::line_search_steps, "[1, 60]", "step halvings before a rejection")
      .require(integer_at_least(1));
  s.add("q_track", &O::q_track, "[0, inf)", "weight of the straight-line reference").require(number_at_least(0));
  s.add("r_input", &O::r_input, "(0, inf)", "input weight").require(number_above(0));
  s.add("q_terminal", &O::q_terminal, "[0, inf)", "terminal weight towards the goal centre").require(number_at_least(0));
  // Its length (the product state dimension) is known only at solve time (InvalidInput there).
  s.add("q_state", &O::q_state, "[] or n numbers >= 0",
        "factors on q_track per product state coordinate (agents in file order); [] for all 1")
      .require({[](const std::vector<double>& q) {
                  for (double w : q)
                    if (!(w >= 0) || !std::isfinite(w)) return false;
                  return true;
                },
                "expected finite numbers >= 0"});
  s.add("bend", &O::bend, "[0, inf)", "sideways bend of the reference per unit path length").require(number_at_least(0));
  s.add("bend_search", &O::bend_search, "true or false",
        "teams: bend the references up to 4 x further where they cut into pair requirements");
  s.add("polish_iterations", &O::polish_iterations, "[0, inf)",
        "final projection steps onto the active constraints (0: none)")
      .require(integer_at_least(0));
  s.add("polish_start", &O::polish_start, "[0, inf)",
        "violation below which the projection is tried before further penalty rounds")
      .require(number_at_least(0));
  s.add("polish_max_violation", &O::polish_max_violation, "(0, inf)", "the projection runs only below this violation")
      .require(number_above(0));
  s.add("polish_active_rounds", &O::polish_active_rounds, "[1, inf)",
        "least-norm solves per projection step: satisfied rows the step would break join the violated ones")
      .require(integer_at_least(1));
  s.add("polish_max_work", &O::polish_max_work, "(0, inf)",
        "skip the projection when the sum over agents of rows_a^2 x T x m_a exceeds this (rows_a: the active rows reading agent a)")
      .require(number_above(0));
  s.choice("coupling", &O::coupling, {"exact", "block", "auto"},
           "backward pass: one group (exact Gauss-Newton) or one group per agent (majorizer)");
  s.add("exact_max_states", &O::exact_max_states, "[1, inf)", "auto: exact up to this many states")
      .require(integer_at_least(1));
  s.add("broad_phase", &O::broad_phase, "true or false",
        "skip pair rows whose agents are beyond their reach (same plan, less work)");
  s.integer("threads", 0, 256,
            "threads for Jacobians, rollouts, costs and the backward pass (0: the machine's, at most 8; same plan for "
            "any number)",
            Checked::on_read, &O::threads);
  return s;
}

}  // namespace

std::vector<ParamSpec> Options::specs() { return declared_once<declare>().specs(); }

Options Options::from(const Params& p) { return declared_once<declare>().parse(p); }

}  // namespace marsyn::altro
