#pragma once
// What nlopt, ipopt and ompl answer before they build anything: a request without a problem or
// without a positive horizon is PlannerStatus::InvalidInput, in the same words from each.
#include <optional>

#include "marsyn/planner.hpp"

namespace marsyn::planner_support {

inline std::optional<PlanResult> invalid_input(const PlanningProblem& pp) {
  if (pp.problem && pp.horizon > 0) return std::nullopt;
  PlanResult res;
  res.status = PlannerStatus::InvalidInput;
  res.message = "no problem or a non-positive horizon";
  return res;
}

}  // namespace marsyn::planner_support
