// The "nlopt" planner plugin: single shooting with NLopt behind the Planner interface.
#include "marsyn/plugin.hpp"
#include "nlopt_solver.hpp"

namespace {

class NloptPlanner final : public marsyn::Planner {
 public:
  explicit NloptPlanner(const marsyn::Params& p) : options_(marsyn::nlopt_planner::Options::from(p)) {}
  static std::vector<marsyn::ParamSpec> param_specs() { return marsyn::nlopt_planner::Options::specs(); }
  std::string name() const override { return "nlopt"; }
  marsyn::PlanResult solve(const marsyn::PlanningProblem& problem, const marsyn::PlanOptions& options) const override {
    return marsyn::nlopt_planner::solve(problem, options, options_);
  }

 private:
  marsyn::nlopt_planner::Options options_;
};

}  // namespace

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::Planner, NloptPlanner>(
    "nlopt", "single shooting with exact gradients, NLopt augmented Lagrangian (small problems)"))
