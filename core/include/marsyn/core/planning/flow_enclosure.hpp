#pragma once
// Where the disturbance-free flow from one state goes between two samples: the continuous
// nominal that the continuous-time robust check (robust_check.hpp) holds to the spec.
#include <vector>

#include <Eigen/Core>

#include "marsyn/box.hpp"
#include "marsyn/dynamics.hpp"

namespace marsyn::planning {

// out[s] (s < parts) encloses x(t) for t in the s-th of `parts` equal parts of [0, tau], for
// x' = f(x, u) + w(t), x(0) in the box `start`, every measurable w with values in [-w, w] (the
// exact flow, not RK4). Each part: a Picard a priori box B with X + [0, h] (F(B) + W) inside B
// (docs/soundness.md §4a), then X' = (X + h (F(B) + W)) ∩ B. Returns false when no a priori box
// is found (a part the check then cannot clear).
bool flow_boxes(const Dynamics& f, const Box& start, const Eigen::VectorXd& u, const Eigen::VectorXd& w, double tau,
                int parts, std::vector<Box>& out);

}  // namespace marsyn::planning
