#pragma once
// Solve options for the core tests of the outer search: five verification runs (the tests judge
// the search, not the runs), no global abstraction, and the log kept when asked.
#include <string>
#include <vector>

#include "marsyn/core/solve.hpp"

namespace marsyn::test {

inline SolveOptions quick_solve(std::vector<std::string>* log = nullptr) {
  SolveOptions so;
  so.verification_runs = 5;
  so.global_memory_budget_bytes = 0;
  if (log) so.log = [log](const std::string& s) { log->push_back(s); };
  return so;
}

}  // namespace marsyn::test
