// The planner's typed parameters, each declared once (marsyn/param_set.hpp): name, range and doc
// here, the default in Options (ompl_solver.hpp); listing, parsing and checks read this one
// declaration. (Options::feasibility_tolerance is not a parameter.)
#include "marsyn/param_set.hpp"
#include "ompl_solver.hpp"

namespace marsyn::ompl_planner {

namespace {

ParamSet<Options> declare() {
  using O = Options;
  const Rule<double> positive{[](const double& v) { return v > 0; }, "must be positive"};
  const Rule<int> at_least_one{[](const int& v) { return !(v < 1); }, "must be at least 1"};
  ParamSet<O> s;
  s.choice("planner", &O::planner, {"sst", "rrt", "kpiece1"}, "OMPL control planner");
  s.add("time_limit", &O::time_limit_s, "(0, inf)", "planning time in seconds (the run's limit also applies)")
      .require_last(positive);
  s.add("goal_bias", &O::goal_bias, "[0, 1]", "probability of sampling the goal box")
      .require_last({[](const double& v) { return !(v < 0 || v > 1); }, "must be in [0, 1]"});
  // Positive: elapsed time is what bounds paths by the horizon and identifies the start.
  s.add("time_weight", &O::time_weight, "(0, inf)", "weight of elapsed time (per second) in OMPL's state distance")
      .require_last(positive);
  s.add("selection_radius", &O::selection_radius, "(0, inf)", "SST selection radius");
  s.add("pruning_radius", &O::pruning_radius, "(0, inf)", "SST pruning radius");
  s.add("seed", &O::seed, "-1 or [0, inf)", "OMPL's process-wide RNG seed, set once (-1: random)");
  // Checked as soon as it is read: it has always been reported before the numbers' rules.
  s.add("max_control_steps", &O::max_control_steps, "[1, inf)", "longest hold of one sampled control, in steps of tau")
      .require(at_least_one);
  s.add("hold_candidates", &O::hold_candidates, "[1, inf)", "controls tried per step to hold the state in the goal")
      .require_last(at_least_one);
  return s;
}

}  // namespace

std::vector<ParamSpec> Options::specs() { return declared_once<declare>().specs(); }

Options Options::from(const Params& p) { return declared_once<declare>().parse(p); }

}  // namespace marsyn::ompl_planner
