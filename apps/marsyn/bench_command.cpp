// `marsyn bench`: runs chosen planners (stage "plan", tracking included unless --no-track) or the
// whole method (stage "solve") on chosen examples and prints a table, also written as CSV and
// markdown. Every figure is measured in this process, on this machine.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "commands.hpp"
#include "marsyn/core/planning/plan.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/setup.hpp"
#include "marsyn/number_text.hpp"

namespace fs = std::filesystem;

namespace marsyn::cli {
namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

std::string resolve_example(const std::string& name) {
  if (fs::exists(name)) return name;
  const fs::path dir = fs::path(default_example()).parent_path();
  for (const auto& candidate : {dir / name, dir / (name + ".yaml")})
    if (fs::exists(candidate)) return candidate.string();
  throw std::runtime_error("no example '" + name + "' (looked in " + dir.string() + ")");
}

struct Row {
  std::vector<std::string> cells;
};

void emit(const std::string& out_dir, const std::vector<std::string>& head, const std::vector<Row>& rows) {
  std::vector<std::size_t> w(head.size());
  for (std::size_t c = 0; c < head.size(); ++c) {
    w[c] = head[c].size();
    for (const auto& r : rows) w[c] = std::max(w[c], r.cells[c].size());
  }
  auto line = [&](const std::vector<std::string>& cells) {
    for (std::size_t c = 0; c < cells.size(); ++c) std::printf("%-*s  ", static_cast<int>(w[c]), cells[c].c_str());
    std::printf("\n");
  };
  line(head);
  for (const auto& r : rows) line(r.cells);
  fs::create_directories(out_dir);
  std::ofstream csv(fs::path(out_dir) / "bench.csv"), md(fs::path(out_dir) / "bench.md");
  for (std::size_t c = 0; c < head.size(); ++c) {
    csv << (c ? "," : "") << head[c];
    md << "| " << head[c] << " ";
  }
  csv << "\n";
  md << "|\n";
  for (std::size_t c = 0; c < head.size(); ++c) md << "|---";
  md << "|\n";
  for (const auto& r : rows) {
    for (std::size_t c = 0; c < r.cells.size(); ++c) {
      csv << (c ? "," : "") << r.cells[c];
      md << "| " << r.cells[c] << " ";
    }
    csv << "\n";
    md << "|\n";
  }
  std::printf("\nwrote %s/bench.csv and %s/bench.md\n", out_dir.c_str(), out_dir.c_str());
}

}  // namespace

int run_bench(const std::string& examples_list, const std::string& planners_list, const std::string& stage,
              bool track, int runs, int threads, const std::string& out_dir, const LoadOptions& load) {
  std::vector<std::string> examples = split(examples_list);
  if (examples.empty()) examples = {"pendulum", "crane_vehicle", "multi_drone", "lane_merging", "formation"};
  std::vector<Row> rows;
  if (stage == "solve") {
    const std::vector<std::string> head = {"example", "status", "T_plan s", "N_l (max)", "T_abs s (max)", "T_syn s (max)",
                                           "verify runs", "violations", "open-loop viol.", "total s"};
    for (const auto& ex : examples) {
      Setup setup(load_problem(resolve_example(ex), load));
      SolveOptions so = solve_options_for(setup.loaded());  // the file's search.time_limit, as `solve` obeys it
      so.verification_runs = runs;
      so.threads = threads;
      std::fprintf(stderr, "[bench] solve %s ...\n", ex.c_str());
      const SolveOutcome o = setup.solve(so);
      double nl = 0, ta = 0, ts = 0;
      for (const auto& a : o.agents) {
        nl = std::max(nl, a.track.stats.state_input_pairs);
        ta = std::max(ta, a.track.stats.abstraction_time_s);
        ts = std::max(ts, a.track.stats.synthesis_time_s);
      }
      rows.push_back(
          {{ex, o.verified ? "verified" : "failed", number_text(o.plan.total_time_s, 3), number_text(nl, 3),
            number_text(ta, 3), number_text(ts, 3), std::to_string(o.verification.runs),
            std::to_string(o.verification.violations),
            std::to_string(o.verification.open_loop_violations) + "/" + std::to_string(o.verification.open_loop_runs),
            number_text(o.total_time_s, 3)}});
    }
    emit(out_dir, head, rows);
    return 0;
  }
  const std::vector<std::string> head = {"example", "planner", "feasible", "plan s", "iterations", "cost",
                                         "min robust margin", "horizon", "tracking"};
  for (const auto& ex : examples) {
    Setup setup(load_problem(resolve_example(ex), load));
    std::vector<std::string> planners = split(planners_list);
    if (planners.empty()) planners = setup.loaded().registry->names("planner");
    for (const auto& name : planners) {
      Problem pb = setup.problem();
      if (pb.planner.name != name) pb.planner = {name, {}};  // the config's parameters belong to its own planner
      pb.warm_start_planner = {};  // each planner measured alone, without the config's chain
      try {
        setup.planner(pb.planner);
      } catch (const std::exception& e) {
        rows.push_back({{ex, name, "error", "-", "-", "-", "-", "-", e.what()}});
        continue;
      }
      std::fprintf(stderr, "[bench] %s with %s ...\n", ex.c_str(), name.c_str());
      const planning::PlanOutcome o = setup.plan(pb, {});
      std::string tracking = "-";
      if (track && o.feasible) {
        SolveOptions so;
        so.threads = threads;
        const auto agents = setup.track(pb, o.nominal, so);
        int ok = 0;
        for (const auto& a : agents) ok += a.track.status == TrackerStatus::ControllerFound;
        tracking = std::to_string(ok) + "/" + std::to_string(agents.size()) + " agents";
      }
      const bool has_plan = !o.plan.u.empty();
      rows.push_back({{ex, name, o.feasible ? "yes" : "no (" + std::string(to_string(o.result.status)) + ")",
                       number_text(o.total_time_s, 3), std::to_string(o.result.iterations),
                       has_plan ? number_text(o.result.cost, 3) : "-",
                       has_plan ? number_text(o.check.min_margin, 3) : "-", std::to_string(o.horizon), tracking}});
    }
  }
  emit(out_dir, head, rows);
  return 0;
}

}  // namespace marsyn::cli
