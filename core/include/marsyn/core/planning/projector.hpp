#pragma once
// Step 2 of the method: the product plan split into one nominal trajectory per agent.
#include "marsyn/projector.hpp"

namespace marsyn::planning {

class ProductProjector final : public Projector {
 public:
  std::vector<NominalTrajectory> project(const Problem& problem, const GlobalPlan& plan) const override;
};

}  // namespace marsyn::planning
