#pragma once
// The output folder of `marsyn solve`: result.json, plan.json, one controller file per agent
// and report.html, written all-or-nothing.
#include <string>
#include <vector>

#include "marsyn/core/solve.hpp"

namespace marsyn {

// Writes the files into out_dir and returns their names.
std::vector<std::string> write_solve_outputs(const std::string& out_dir, SolveOutcome& outcome);

}  // namespace marsyn
