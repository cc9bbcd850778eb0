#pragma once
// The knobs of one `marsyn solve` run (threads, budgets, the progress sink), shared by the
// orchestrator and the stages it drives.
#include <functional>
#include <string>

namespace marsyn {

struct SolveOptions {
  int verification_runs = 1000;
  int threads = 2;
  int max_outer_iterations = 4;             // bounded search
  double time_limit_s = 600.0;
  double global_memory_budget_bytes = 2e9;  // the global ABCD baseline is attempted below this
  std::function<void(const std::string&)> log;  // progress lines; may be empty
};

}  // namespace marsyn
