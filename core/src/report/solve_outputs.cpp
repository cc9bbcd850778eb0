#include "marsyn/core/report/solve_outputs.hpp"

#include <filesystem>
#include <fstream>

#include "marsyn/core/planning/plan_io.hpp"
#include "marsyn/core/report/output_folder.hpp"
#include "marsyn/core/report/report_html.hpp"
#include "marsyn/core/report/result_json.hpp"

namespace fs = std::filesystem;

namespace marsyn {

namespace {
std::vector<std::string> write_into(const std::string& dir, SolveOutcome& o);
}

// The output rule (docs/problem-format.md, "Output files"): a verified solve writes result.json,
// report.html, plan.json and one <agent>.ctrl per agent; a failed or stopped one writes
// result.json (status "failed" or "stopped", the reason, "partial"), report.html, plan.json when
// it has a plan, and the controllers it found (each sound for its agent's tube, so a resumed or
// inspected run loses nothing; none is the team's guarantee). Everything goes through OutputFolder (plain
// names, checked after path resolution to lie in `dir`). Files are staged in a hidden folder
// inside `dir` and moved in only when all are written, so a failure part-way never leaves a
// half-written result; marsyn's own earlier files for this problem are replaced, nothing else in
// `dir` is touched.
std::vector<std::string> write_solve_outputs(const std::string& dir, SolveOutcome& o) {
  const OutputFolder folder(dir);
  const fs::path staging = folder.path(".marsyn-partial");
  fs::remove_all(staging);
  fs::create_directory(staging);
  try {
    auto files = write_into(staging.string(), o);
    std::vector<std::string> previous = {"result.json", "report.html", "plan.json"};
    for (const auto& a : o.problem.agents) previous.push_back(a.name + ".ctrl");
    for (const auto& f : previous) fs::remove(folder.path(f));
    for (const auto& f : files) fs::rename(staging / f, folder.path(f));
    fs::remove_all(staging);
    return files;
  } catch (...) {
    std::error_code ec;
    fs::remove_all(staging, ec);
    throw;
  }
}

namespace {
std::vector<std::string> write_into(const std::string& dir, SolveOutcome& o) {
  std::vector<std::string> files;
  for (auto& a : o.agents) a.controller_file.clear();
  for (auto& a : o.agents) {
    if (!a.track.controller) continue;
    a.controller_file = a.name + ".ctrl";
    a.track.controller->write((fs::path(dir) / a.controller_file).string());
    files.push_back(a.controller_file);
  }
  if (o.plan.feasible && !o.plan.plan.u.empty()) {
    planning::write_plan_json((fs::path(dir) / "plan.json").string(), o.problem, o.plan);
    files.push_back("plan.json");
  }
  const nlohmann::json result = result_json(o);
  {
    std::ofstream f(fs::path(dir) / "result.json");
    f << result.dump(2) << "\n";
    if (!f) throw std::runtime_error("cannot write " + (fs::path(dir) / "result.json").string());
  }
  files.push_back("result.json");
  std::vector<const std::vector<PeriodEnclosure>*> enclosures;
  for (const auto& a : o.agents) enclosures.push_back(a.track.controller ? &a.track.controller->period_enclosures() : nullptr);
  const nlohmann::json scene =
      report_scene(planning::with_visits(o.problem, o.plan.visits), o.plan.nominal, o.verification_ran ? &o.verification : nullptr, enclosures);
  write_report_html((fs::path(dir) / "report.html").string(), result, scene);
  files.push_back("report.html");
  return files;
}
}  // namespace

}  // namespace marsyn
