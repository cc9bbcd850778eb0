// The "ipopt" planner plugin: direct multiple shooting with Ipopt behind the Planner interface.
#include "ipopt_solver.hpp"
#include "marsyn/plugin.hpp"

namespace {

class IpoptPlanner final : public marsyn::Planner {
 public:
  explicit IpoptPlanner(const marsyn::Params& p) : options_(marsyn::ipopt_planner::Options::from(p)) {}
  static std::vector<marsyn::ParamSpec> param_specs() { return marsyn::ipopt_planner::Options::specs(); }
  std::string name() const override { return "ipopt"; }
  marsyn::PlanResult solve(const marsyn::PlanningProblem& problem, const marsyn::PlanOptions& options) const override {
    return marsyn::ipopt_planner::solve(problem, options, options_);
  }

 private:
  marsyn::ipopt_planner::Options options_;
};

}  // namespace

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::Planner, IpoptPlanner>(
    "ipopt", "direct multiple shooting with Ipopt (sparse exact Jacobian, differenced Hessian), eps-robust"))
