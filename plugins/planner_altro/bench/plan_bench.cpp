// marsyn_plan_bench [scenario...] [--repeat N] [--verbose] [--out DIR] [--param name=value]
//                   [--corner c]: plans each scenario with the altro
// planner through core's plan() (assembly, solve, clamping, exact eps-robust check) and prints
// wall time, iterations, solver violation and the smallest robust margin.
#include <ctime>
#include <cstdio>
#include <cstring>
#include <iostream>

#include "altro_solver.hpp"
#include "marsyn/core/planning/plan_io.hpp"
#include "marsyn/stopwatch.hpp"
#include "plan_scenarios.hpp"

namespace {

class Altro final : public marsyn::Planner {
 public:
  explicit Altro(const marsyn::Params& p) : o_(marsyn::altro::Options::from(p)) {}
  std::string name() const override { return "altro"; }
  marsyn::PlanResult solve(const marsyn::PlanningProblem& p, const marsyn::PlanOptions& r) const override {
    return marsyn::altro::solve(p, r, o_);
  }

 private:
  marsyn::altro::Options o_;
};

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> names;
  int repeat = 1;
  bool verbose = false;
  std::string dump;
  marsyn::Params overrides;
  double corner = -1;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--verbose")) verbose = true;
    else if (!std::strcmp(argv[i], "--out") && i + 1 < argc) dump = argv[++i];
    else if (!std::strcmp(argv[i], "--corner") && i + 1 < argc) corner = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--param") && i + 1 < argc) {  // name=value (numbers or text)
      const std::string kv = argv[++i];
      const auto eq = kv.find('=');
      const std::string k = kv.substr(0, eq), v = kv.substr(eq + 1);
      char* end = nullptr;
      const double d = std::strtod(v.c_str(), &end);
      if (end && *end == 0) {
        if (v.find_first_of(".eE") == std::string::npos) overrides.set(k, static_cast<long>(d));
        else overrides.set(k, d);
      } else {
        overrides.set(k, v);
      }
    }
    else names.push_back(argv[i]);
  }
  if (names.empty()) names = marsyn::bench::scenario_names();
  std::printf("%-18s %4s %5s %4s %-11s %6s %9s %9s %7s %10s %10s  %s\n", "scenario", "N", "n", "T", "status",
              "iters", "solve_s", "total_s", "cpu_s", "violation", "margin", "robust (smallest margin at)");
  int failures = 0;
  for (const auto& name : names) {
    auto sc = marsyn::bench::make_scenario(name);
    for (const auto& [k, v] : overrides.values()) sc.planner_params.set(k, v);
    const Altro planner(sc.planner_params);
    marsyn::planning::PlanSearchOptions so;
    if (corner > 0) so.assembly.inf_norm_corner = corner;
    if (verbose) so.log = [](const std::string& s) { std::cerr << "  " << s << "\n"; };
    double best = 1e300, cpu = 0;
    marsyn::planning::PlanOutcome out;
    for (int r = 0; r < repeat; ++r) {
      const marsyn::Stopwatch wall;
      const std::clock_t c0 = std::clock();
      out = marsyn::planning::plan(sc.problem, planner, so);
      cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
      best = std::min(best, wall.seconds());
    }
    const auto& p = sc.problem;
    std::printf("%-18s %4zu %5d %4d %-11s %6d %9.3f %9.3f %7.3f %10.2e %10.4f  %s\n", name.c_str(), p.agents.size(),
                p.product_state_dim(), out.horizon, marsyn::to_string(out.result.status), out.result.iterations,
                out.result.solve_time_s, best, cpu, out.result.max_violation, out.check.min_margin,
                (std::string(out.feasible ? "yes" : "NO") + " (" + out.check.worst + ")").c_str());
    if (verbose) std::cerr << "  " << out.result.message << "\n";
    if (!dump.empty()) {
      marsyn::planning::write_plan_json(dump + "/" + name + ".json", p, out);
      marsyn::planning::write_agent_csvs(dump + "/" + name, p, out);
    }
    std::fflush(stdout);
    failures += !out.feasible;
  }
  return failures == 0 ? 0 : 1;
}
