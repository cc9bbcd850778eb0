#pragma once
// Step 2 of the method: the product plan split into one nominal trajectory per agent. A named
// stage of core, not a plugin kind: projecting is reading each agent's coordinates back out of the
// product, and any other projection would break what the robust plan promises each agent
// (docs/architecture.md, "Why projection is not a plugin kind").
#include <vector>

#include "marsyn/problem.hpp"

namespace marsyn::planning {

class Projector {
 public:
  virtual ~Projector() = default;
  virtual std::vector<NominalTrajectory> project(const Problem& problem, const GlobalPlan& plan) const = 0;
};

class ProductProjector final : public Projector {
 public:
  std::vector<NominalTrajectory> project(const Problem& problem, const GlobalPlan& plan) const override;
};

}  // namespace marsyn::planning
