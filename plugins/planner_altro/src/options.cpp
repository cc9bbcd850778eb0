// The solver's typed parameters: declaration (for the loader and `marsyn plugins --params`) and
// parsing with range checks.
#include <cmath>
#include <sstream>

#include "altro_solver.hpp"

namespace marsyn::altro {

std::vector<ParamSpec> Options::specs() {
  const Options d;
  auto s = [](double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  };
  return {
      {"max_iterations", ParamType::Int, s(d.max_iterations), "[1, inf)", "iLQR iterations in total"},
      {"max_outer", ParamType::Int, s(d.max_outer), "[1, inf)", "augmented-Lagrangian (multiplier) updates"},
      {"max_inner", ParamType::Int, s(d.max_inner), "[1, inf)", "iLQR iterations per multiplier update"},
      {"cost_tolerance", ParamType::Real, s(d.cost_tolerance), "(0, inf)",
       "relative cost decrease ending an inner solve near feasibility"},
      {"cost_tolerance_intermediate", ParamType::Real, s(d.cost_tolerance_intermediate), "(0, inf)",
       "relative cost decrease ending an inner solve while infeasible"},
      {"constraint_tolerance", ParamType::Real, s(d.constraint_tolerance), "(0, inf)",
       "largest constraint violation accepted as converged"},
      {"penalty_initial", ParamType::Real, s(d.penalty_initial), "(0, inf)", "initial penalty rho"},
      {"penalty_scaling", ParamType::Real, s(d.penalty_scaling), "(1, inf)", "rho factor per outer update"},
      {"penalty_max", ParamType::Real, s(d.penalty_max), "(0, inf)", "largest penalty"},
      {"reg_initial", ParamType::Real, s(d.reg_initial), "[0, inf)", "initial regularization of Quu"},
      {"reg_min", ParamType::Real, s(d.reg_min), "[0, inf)", "smallest regularization"},
      {"reg_max", ParamType::Real, s(d.reg_max), "(0, inf)", "largest regularization (beyond: stalled)"},
      {"reg_factor", ParamType::Real, s(d.reg_factor), "(1, inf)", "regularization change factor"},
      {"small_step", ParamType::Real, s(d.small_step), "(0, 1]", "accepted steps this short raise regularization"},
      {"line_search_steps", ParamType::Int, s(d.line_search_steps), "[1, 60]", "step halvings before a rejection"},
      {"q_track", ParamType::Real, s(d.q_track), "[0, inf)", "weight of the straight-line reference"},
      {"r_input", ParamType::Real, s(d.r_input), "(0, inf)", "input weight"},
      {"q_terminal", ParamType::Real, s(d.q_terminal), "[0, inf)", "terminal weight towards the goal centre"},
      {"q_state", ParamType::RealVector, "[]", "[] or n numbers >= 0",
       "factors on q_track per product state coordinate (agents in file order); [] for all 1"},
      {"bend", ParamType::Real, s(d.bend), "[0, inf)", "sideways bend of the reference per unit path length"},
      {"polish_iterations", ParamType::Int, s(d.polish_iterations), "[0, inf)",
       "final projection steps onto the active constraints (0: none)"},
      {"polish_start", ParamType::Real, s(d.polish_start), "[0, inf)",
       "violation below which the projection is tried before further penalty rounds"},
      {"polish_max_violation", ParamType::Real, s(d.polish_max_violation), "(0, inf)",
       "the projection runs only below this violation"},
      {"polish_max_work", ParamType::Real, s(d.polish_max_work), "(0, inf)",
       "skip the projection when rows^2 x T x m exceeds this (dense least squares)"},
      {"coupling", ParamType::String, d.coupling, "exact|block|auto",
       "backward pass: one group (exact Gauss-Newton) or one group per agent (majorizer)"},
      {"exact_max_states", ParamType::Int, s(d.exact_max_states), "[1, inf)", "auto: exact up to this many states"},
  };
}

Options Options::from(const Params& p) {
  Options o;
  auto pos_int = [&](const char* name, int& v, long lo) {
    const long x = p.integer(name, v);
    if (x < lo) throw ParamError(name, "expected an integer >= " + std::to_string(lo));
    v = static_cast<int>(x);
  };
  auto pos = [&](const char* name, double& v, double lo, bool strict) {
    const double x = p.real(name, v);
    if (!(strict ? x > lo : x >= lo)) throw ParamError(name, std::string("expected a number ") + (strict ? ">" : ">=") + " " + std::to_string(lo));
    v = x;
  };
  pos_int("max_iterations", o.max_iterations, 1);
  pos_int("max_outer", o.max_outer, 1);
  pos_int("max_inner", o.max_inner, 1);
  pos_int("line_search_steps", o.line_search_steps, 1);
  pos_int("exact_max_states", o.exact_max_states, 1);
  pos_int("polish_iterations", o.polish_iterations, 0);
  pos("polish_max_violation", o.polish_max_violation, 0, true);
  pos("polish_start", o.polish_start, 0, false);
  pos("polish_max_work", o.polish_max_work, 0, true);
  pos("cost_tolerance", o.cost_tolerance, 0, true);
  pos("cost_tolerance_intermediate", o.cost_tolerance_intermediate, 0, true);
  pos("constraint_tolerance", o.constraint_tolerance, 0, true);
  pos("penalty_initial", o.penalty_initial, 0, true);
  pos("penalty_scaling", o.penalty_scaling, 1, true);
  pos("penalty_max", o.penalty_max, 0, true);
  pos("reg_initial", o.reg_initial, 0, false);
  pos("reg_min", o.reg_min, 0, false);
  pos("reg_max", o.reg_max, 0, true);
  pos("reg_factor", o.reg_factor, 1, true);
  pos("small_step", o.small_step, 0, true);
  pos("q_track", o.q_track, 0, false);
  pos("r_input", o.r_input, 0, true);
  pos("q_terminal", o.q_terminal, 0, false);
  pos("bend", o.bend, 0, false);
  o.q_state = p.reals("q_state", o.q_state);
  for (double w : o.q_state)
    if (!(w >= 0) || !std::isfinite(w)) throw ParamError("q_state", "expected finite numbers >= 0");
  o.coupling = p.text("coupling", o.coupling);
  if (o.coupling != "exact" && o.coupling != "block" && o.coupling != "auto")
    throw ParamError("coupling", "expected exact, block or auto");
  if (o.small_step > 1) throw ParamError("small_step", "expected a number in (0, 1]");
  return o;
}

}  // namespace marsyn::altro
