#pragma once
// Step 2 of the method: split a product plan into one nominal trajectory per agent.
#include <vector>

#include "marsyn/problem.hpp"

namespace marsyn {

class Projector {
 public:
  virtual ~Projector() = default;
  virtual std::vector<NominalTrajectory> project(const Problem& problem, const GlobalPlan& plan) const = 0;
};

}  // namespace marsyn
