#pragma once
// The scalar types every model's vector field is evaluated with.
#include "marsyn/dual.hpp"
#include "marsyn/interval.hpp"

namespace marsyn {
using DualD = Dual<double>;    // exact Jacobians (planners)
using DualI = Dual<Interval>;  // Jacobian enclosures over boxes (growth bounds)
}  // namespace marsyn
