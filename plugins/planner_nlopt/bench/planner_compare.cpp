// marsyn_planner_compare: every available planner on chosen examples, each through core's
// planning::plan (assembly, solve, clamp, re-simulation, exact robust check), one table row per
// pair. Planners come from the plugin registry, so the altro/nlopt/ipopt/ompl plugins built next
// to this program are found without configuration.
//
//   marsyn_planner_compare [--examples DIR] [--cases pendulum,crane_vehicle,multi_drone]
//                          [--planners altro,nlopt,ipopt,ompl] [--time-limit S] [--attempts N]
//                          [--csv FILE] [--set PLANNER.PARAM=VALUE]... [--warm-from PLANNER]
//
// --warm-from P adds, per example, a row "Q<-P" for every other planner Q: Q solves the same
// horizon starting from P's feasible plan (PlanningProblem::warm_start), then the exact check.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "marsyn/core/planning/plan.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/number_text.hpp"
#include "marsyn/stopwatch.hpp"

using namespace marsyn;

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

struct Row {
  std::string planner, example, status, note;
  bool feasible = false;
  int horizon = 0, iterations = 0;
  double time_s = 0, cost = 0, margin = 0;
};

}  // namespace

int main(int argc, char** argv) {
  std::string dir = MARSYN_EXAMPLES_DIR, csv;
  std::vector<std::string> cases = {"pendulum", "crane_vehicle", "multi_drone"};
  std::vector<std::string> planners = {"altro", "nlopt", "ipopt", "ompl"};
  double limit = 120;
  int attempts = 1;
  std::vector<std::string> sets;  // planner.param=value
  std::string warm_from;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--examples") dir = v;
    else if (a == "--cases") cases = split(v);
    else if (a == "--planners") planners = split(v);
    else if (a == "--time-limit") limit = std::stod(v);
    else if (a == "--attempts") attempts = std::stoi(v);
    else if (a == "--csv") csv = v;
    else if (a == "--set") sets.push_back(v);
    else if (a == "--warm-from") warm_from = v;
    else {
      std::cerr << "unknown option " << a << "\n";
      return 2;
    }
  }
  auto params_for = [&](const std::string& name) {
    Params params;
    if (name == "ompl") params.set("time_limit", limit);
    for (const auto& kv : sets) {
      const auto dot = kv.find('.'), eq = kv.find('=');
      if (dot == std::string::npos || eq == std::string::npos || kv.substr(0, dot) != name) continue;
      const std::string key = kv.substr(dot + 1, eq - dot - 1), val = kv.substr(eq + 1);
      char* end = nullptr;
      const double num = std::strtod(val.c_str(), &end);
      if (end && *end == '\0' && !val.empty()) {
        if (val.find_first_of(".eE") == std::string::npos) params.set(key, static_cast<long>(num));
        else params.set(key, num);
      } else if (val == "true" || val == "false") {
        params.set(key, val == "true");
      } else {
        params.set(key, val);
      }
    }
    return params;
  };
  std::vector<Row> rows;
  for (const auto& c : cases) {
    LoadedProblem lp = load_problem(dir + "/" + c + ".yaml");
    std::optional<planning::PlanOutcome> warm;
    for (const auto& name : planners) {
      Row r;
      r.planner = name;
      r.example = c;
      if (!lp.registry->find("planner", name)) {
        r.status = "not installed";
        rows.push_back(r);
        continue;
      }
      auto planner = lp.registry->create<Planner>(name, params_for(name));
      planning::PlanSearchOptions so;
      so.max_attempts = attempts;
      so.time_limit_s = limit;
      const auto out = planning::plan(lp.problem, *planner, so);
      if (name == warm_from && out.feasible) warm = out;
      r.feasible = out.feasible;
      r.status = to_string(out.result.status);
      r.horizon = out.horizon;
      r.iterations = out.result.iterations;
      r.time_s = out.total_time_s;
      r.cost = out.result.cost;
      r.margin = out.check.min_margin;
      r.note = out.feasible ? out.check.worst : (out.result.message + "; " + out.check.message);
      rows.push_back(r);
      std::cerr << name << " on " << c << ": " << (r.feasible ? "feasible" : "not feasible") << " in " << r.time_s
                << " s (" << r.status << ") " << out.result.message << "\n";
    }
    if (!warm) continue;
    for (const auto& name : planners) {
      // OMPL grows its tree from x0 and does not read warm_start.
      if (name == warm_from || name == "ompl" || !lp.registry->find("planner", name)) continue;
      Row r;
      r.planner = name + "<-" + warm_from;
      r.example = c;
      auto planner = lp.registry->create<Planner>(name, params_for(name));
      PlanningProblem pp = planning::assemble(lp.problem, warm->horizon);
      pp.warm_start = warm->plan;
      PlanOptions po;
      po.time_limit_s = limit;
      const Stopwatch clock;
      PlanResult res = planner->solve(pp, po);
      r.time_s = clock.seconds();
      GlobalPlan plan = res.plan;
      if (static_cast<int>(plan.u.size()) == warm->horizon) {
        for (auto& u : plan.u)
          for (int j = 0; j < u.size(); ++j) u[j] = std::clamp(u[j], pp.input_bounds.lo[j], pp.input_bounds.hi[j]);
        const auto check = planning::check_robust(lp.problem, plan);
        r.feasible = check.passed;
        r.margin = check.min_margin;
        r.note = res.message + "; " + check.message;
      } else {
        r.margin = -INFINITY;
        r.note = res.message + "; no inputs";
      }
      r.status = to_string(res.status);
      r.horizon = warm->horizon;
      r.iterations = res.iterations;
      r.cost = res.cost;
      rows.push_back(r);
      std::cerr << r.planner << " on " << c << ": " << (r.feasible ? "feasible" : "not feasible") << " in " << r.time_s
                << " s (" << r.status << ") " << res.message << "\n";
    }
  }
  std::cout << "| planner | example | success (exact check) | T | plan time [s] | iterations | cost | smallest robust margin | solver status |\n"
            << "|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows)
    std::cout << "| " << r.planner << " | " << r.example << " | " << (r.feasible ? "yes" : "no") << " | " << r.horizon
              << " | " << number_text(r.time_s, 3) << " | " << r.iterations << " | " << number_text(r.cost, 3) << " | "
              << number_text(r.margin, 3) << " | " << r.status << " |\n";
  std::cout << "\nNotes (failures: solver message; exact check):\n";
  for (const auto& r : rows)
    if (!r.feasible) std::cout << "- " << r.planner << " / " << r.example << ": " << r.note << "\n";
  if (!csv.empty()) {
    std::ofstream f(csv);
    f << "planner,example,success,horizon,plan_time_s,iterations,cost,min_margin,status\n";
    for (const auto& r : rows)
      f << r.planner << "," << r.example << "," << (r.feasible ? 1 : 0) << "," << r.horizon << "," << r.time_s << ","
        << r.iterations << "," << r.cost << "," << r.margin << "," << r.status << "\n";
  }
  return 0;
}
