// marsyn_ipopt_hessian_compare: the ipopt planner on the case-study examples with each way of
// computing the Hessian of the Lagrangian, through core's planning::plan (exact robust check).
//
//   marsyn_ipopt_hessian_compare [--cases pendulum,crane_vehicle,multi_drone]
//                                [--hessians differenced,exact,exact-models,limited-memory] [--time-limit S]
//
// `exact` is the plugin as loaded (AD blocks where marsyn::Dynamics / marsyn::Constraint give
// second derivatives, differenced blocks elsewhere). `exact-models` additionally hands the
// planner each agent's vector field with nested duals, taken from the concrete in-tree model
// (dynamic_cast of the loaded model): the dynamics blocks a Dynamics overload for DualD2 would
// make exact (docs/planners.md, ipopt).
#include <chrono>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "dynamics_cartpole/src/cartpole.hpp"
#include "dynamics_double_integrator/src/double_integrator.hpp"
#include "dynamics_pendulum/src/pendulum.hpp"
#include "dynamics_unicycle/src/unicycle.hpp"
#include "ipopt_solver.hpp"
#include "marsyn/core/planning/plan.hpp"
#include "marsyn/core/problem/problem_loader.hpp"

using namespace marsyn;
using ipopt_planner::SecondOrderField;

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

template <class Model>
bool try_field(const Dynamics* d, SecondOrderField& f) {
  const auto* m = dynamic_cast<const Model*>(d);
  if (m) f = [m](const DualD2* x, const DualD2* u, DualD2* dx) { m->vector_field(x, u, dx); };
  return m != nullptr;
}

SecondOrderField model_field(const Dynamics* d) {
  SecondOrderField f;
  if (try_field<models::Pendulum>(d, f) || try_field<models::Unicycle>(d, f) || try_field<models::CartPole>(d, f) ||
      try_field<models::DoubleIntegrator>(d, f))
    return f;
  throw std::runtime_error("no in-tree model for dynamics '" + d->type() + "'");
}

class Ipopt : public Planner {
 public:
  Ipopt(ipopt_planner::Options o, std::vector<SecondOrderField> f) : o_(std::move(o)), f_(std::move(f)) {}
  std::string name() const override { return "ipopt"; }
  PlanResult solve(const PlanningProblem& p, const PlanOptions& r) const override {
    return ipopt_planner::solve(p, r, o_, f_);
  }

 private:
  ipopt_planner::Options o_;
  std::vector<SecondOrderField> f_;
};

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> cases = {"pendulum", "crane_vehicle", "multi_drone"};
  std::vector<std::string> hessians = {"differenced", "exact", "exact-models"};
  double limit = 120;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--cases") cases = split(v);
    else if (a == "--hessians") hessians = split(v);
    else if (a == "--time-limit") limit = std::stod(v);
    else {
      std::cerr << "unknown option " << a << "\n";
      return 2;
    }
  }
  std::cout << "| example | hessian | success (exact check) | T | plan time [s] | iterations | solver message |\n"
            << "|---|---|---|---|---|---|---|\n";
  for (const auto& c : cases) {
    LoadedProblem lp = load_problem(std::string(MARSYN_EXAMPLES_DIR) + "/" + c + ".yaml");
    for (const auto& h : hessians) {
      ipopt_planner::Options o;
      o.hessian = h == "exact-models" ? "exact" : h;
      std::vector<SecondOrderField> fields;
      if (h == "exact-models")
        for (const auto& a : lp.problem.agents) fields.push_back(model_field(a.dynamics.get()));
      Ipopt planner(o, fields);
      planning::PlanSearchOptions so;
      so.max_attempts = 1;
      so.time_limit_s = limit;
      const auto out = planning::plan(lp.problem, planner, so);
      std::cout << "| " << c << " | " << h << " | " << (out.feasible ? "yes" : "no") << " | " << out.horizon << " | "
                << out.total_time_s << " | " << out.result.iterations << " | " << out.result.message << " |"
                << std::endl;
    }
  }
  return 0;
}
