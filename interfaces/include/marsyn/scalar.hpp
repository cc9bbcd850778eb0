#pragma once
// The scalar types every model's vector field is evaluated with.
#include "marsyn/dual.hpp"
#include "marsyn/fast_interval.hpp"
#include "marsyn/interval.hpp"

namespace marsyn {
using DualD = Dual<double>;         // exact Jacobians (planners)
using DualI = Dual<Interval>;       // Jacobian enclosures over boxes
using DualFI = Dual<FastInterval>;  // the same without rounding-mode switches (tracker hot path)
// Hessian enclosures over boxes (forward over forward on FastInterval): the funnel tracker's
// second-order remainder. Every layer is an interval inclusion of the exact derivative.
using DualFI2 = Dual<Dual<FastInterval>>;
}  // namespace marsyn
