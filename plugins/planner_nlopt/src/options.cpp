// The planner's typed parameters, each declared once (marsyn/param_set.hpp): name, range and doc
// here, the default in Options (nlopt_solver.hpp); listing, parsing and checks read this one
// declaration.
#include "marsyn/param_set.hpp"
#include "nlopt_solver.hpp"

namespace marsyn::nlopt_planner {

namespace {

ParamSet<Options> declare() {
  using O = Options;
  // A negative weight of either kind is reported under r_input, as it always was.
  const Rule<double> weight{[](const double& w) { return !(w < 0); }, "weights must be non-negative"};
  ParamSet<O> s;
  s.choice("algorithm", &O::algorithm, {"auglag_lbfgs", "auglag_slsqp", "slsqp", "mma"},
           "NLopt method: augmented Lagrangian around L-BFGS or SLSQP, or SLSQP / MMA on the constraints directly");
  s.add("r_input", &O::r_input, "[0, inf)", "weight of the input energy 1/2 |u|^2").require_last(weight, "r_input");
  s.add("q_terminal", &O::q_terminal, "[0, inf)", "weight of 1/2 |x_T - goal centre|^2").require_last(weight, "r_input");
  s.add("feasibility_tolerance", &O::feasibility_tolerance, "(0, 1e-3)", "largest row violation reported as exact")
      .require_last({[](const double& v) { return v > 0; }, "must be positive"});
  s.add("xtol_rel", &O::xtol_rel, "(0, 1)", "NLopt relative input tolerance");
  s.add("ftol_rel", &O::ftol_rel, "(0, 1)", "NLopt relative objective tolerance");
  s.add("max_evaluations", &O::max_evaluations, "[1, inf)", "objective evaluations in total")
      .require_last({[](const long& v) { return !(v < 1); }, "must be at least 1"});
  s.add("max_dense_entries", &O::max_dense_entries, "(0, inf)",
        "largest dense constraint Jacobian (rows x inputs); larger problems are refused as invalid input");
  return s;
}

}  // namespace

std::vector<ParamSpec> Options::specs() { return declared_once<declare>().specs(); }

Options Options::from(const Params& p) { return declared_once<declare>().parse(p); }

}  // namespace marsyn::nlopt_planner
