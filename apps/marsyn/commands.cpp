#include "commands.hpp"

#include <filesystem>
#include <iostream>

#include "marsyn/core/plugins/plugin_registry.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/problem/problem_advice.hpp"
#include "marsyn/core/problem/problem_summary.hpp"
#include "marsyn/core/solve_options.hpp"
#include "marsyn/core/tracking/tracking_memory.hpp"
#include "marsyn/core/verification/verification.hpp"

namespace marsyn::cli {

int run_plugins(bool show_params) {
  PluginRegistry registry;
  std::cout << "search path:\n";
  for (const auto& p : registry.search_path()) std::cout << "  " << p << "\n";
  std::cout << "\n";
  std::size_t width = 4;
  for (const auto& i : registry.plugins()) width = std::max(width, i.name.size());
  std::printf("%-10s %-*s %s\n", "kind", static_cast<int>(width), "name", "library");
  for (const auto& i : registry.plugins()) {
    std::printf("%-10s %-*s %s\n", i.kind.c_str(), static_cast<int>(width), i.name.c_str(), i.library_path.c_str());
    std::printf("%-10s %-*s   %s\n", "", static_cast<int>(width), "", i.summary.c_str());
    if (show_params)
      for (const auto& p : i.params)
        std::printf("%-10s %-*s   - %s (%s, default %s, range %s): %s\n", "", static_cast<int>(width), "",
                    p.name.c_str(), to_string(p.type), p.default_value.c_str(), p.range.c_str(), p.doc.c_str());
  }
  std::cout.flush();
  for (const auto& p : registry.problems())
    std::cerr << "warning: skipped " << p.library_path << ": " << p.reason << "\n";
  if (registry.plugins().empty()) {
    std::cerr << "error: no plugins found; set MARSYN_PLUGIN_PATH or reinstall marsyn\n";
    return 2;
  }
  return 0;
}

std::string default_example() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec).parent_path();
  for (const fs::path& p : {fs::path(MARSYN_SOURCE_DIR) / "examples/multi_drone.yaml",
                            exe / "../share/marsyn/examples/multi_drone.yaml"})
    if (fs::exists(p, ec)) return p.lexically_normal().string();
  throw std::runtime_error("the default example examples/multi_drone.yaml was not found; give a CONFIG");
}

// "tracking at most about 43.1 MiB (100 controllers kept, ...)": the stage's upper figure at the
// file's horizon with solve's default threads.
std::string tracking_memory_line(const LoadedProblem& loaded) {
  const int threads = SolveOptions{}.threads;
  const TrackingMemory m = tracking_memory(loaded.trackers, threads, loaded.problem.horizon, loaded.problem.horizon);
  const std::size_t agents = loaded.trackers.size();
  const int at_once = m.at_once;
  return "          tracking at most about " + format_bytes(m.bytes()) + " (" + std::to_string(agents) + " controller" +
         (agents == 1 ? "" : "s") + " kept, " + format_bytes(m.kept_bytes) + " in all; " + std::to_string(at_once) +
         (at_once == 1 ? " synthesis" : " syntheses") + " at once, " + format_bytes(m.working_bytes) + ")\n";
}

int run_check(const std::string& config, const LoadOptions& load) {
  const LoadedProblem loaded = load_problem(config, load);
  std::cout << summarize(loaded.problem, loaded.trackers) << "memory    planning about " << format_bytes(loaded.plan_memory.bytes)
            << " at T = " << loaded.problem.horizon << " (" << loaded.plan_memory_source << ": " << loaded.plan_memory.detail
            << "), budget " << format_bytes(loaded.memory_budget.bytes) << " (" << loaded.memory_budget.source << ")\n"
            << tracking_memory_line(loaded)
            << "          verification about " << format_bytes(verification_memory_bytes(loaded.problem))
            << " (the ten runs kept for the report: every state at every 1/" << VerificationOptions{}.fine_substeps
            << " of a period)\n\n"
            << to_text(advise(loaded)) << "\nok: " << config << " is a valid marsyn problem\n";
  return 0;
}

}  // namespace marsyn::cli
