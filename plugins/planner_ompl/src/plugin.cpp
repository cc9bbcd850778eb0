// The "ompl" planner plugin: kinodynamic sampling-based planning behind the Planner interface.
#include "marsyn/plugin.hpp"
#include "ompl_solver.hpp"

namespace {

class OmplPlanner final : public marsyn::Planner {
 public:
  explicit OmplPlanner(const marsyn::Params& p) : options_(marsyn::ompl_planner::Options::from(p)) {}
  static std::vector<marsyn::ParamSpec> param_specs() { return marsyn::ompl_planner::Options::specs(); }
  std::string name() const override { return "ompl"; }
  marsyn::PlanResult solve(const marsyn::PlanningProblem& problem, const marsyn::PlanOptions& options) const override {
    return marsyn::ompl_planner::solve(problem, options, options_);
  }

 private:
  marsyn::ompl_planner::Options options_;
};

}  // namespace

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::Planner, OmplPlanner>(
    "ompl", "kinodynamic sampling (OMPL SST, RRT or KPIECE1) on the product system, exact solutions only"))
