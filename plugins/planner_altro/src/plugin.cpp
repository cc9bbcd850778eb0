// The "altro" planner plugin: the solver in altro_solver.cpp behind the Planner interface.
#include "altro_solver.hpp"
#include "marsyn/plugin.hpp"

namespace {

class AltroPlanner final : public marsyn::Planner {
 public:
  explicit AltroPlanner(const marsyn::Params& p) : options_(marsyn::altro::Options::from(p)) {}
  static std::vector<marsyn::ParamSpec> param_specs() { return marsyn::altro::Options::specs(); }
  std::string name() const override { return "altro"; }
  marsyn::PlanResult solve(const marsyn::PlanningProblem& problem, const marsyn::PlanOptions& options) const override {
    return marsyn::altro::solve(problem, options, options_);
  }
  std::optional<marsyn::PlannerMemory> memory(const marsyn::Problem& problem) const override {
    return marsyn::altro::memory(problem);
  }

 private:
  marsyn::altro::Options options_;
};

}  // namespace

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::Planner, AltroPlanner>(
    "altro", "augmented-Lagrangian iLQR (ALTRO-style) on the product system, eps-robust"))
