#pragma once
// Is d in the zonotope {G xi : |xi|_inf <= 1}? A phase-1 simplex with bounded variables finds
// coefficients xi (n rows, p <= kMaxGenerators columns, dense, Bland's rule). Its answer is only
// a candidate: the controller accepts a state when the residual G xi - d of the clipped xi,
// evaluated in double, is within the stored tolerance, and the verification starts the next
// period from the zonotope grown by that tolerance and the residual's rounding (docs/soundness.md
// section 11), so a wrong or inaccurate solver answer can never let an unverified state in.
namespace marsyn::funnel {

inline constexpr int kMaxMembershipGenerators = 64;
inline constexpr int kMaxMembershipRows = 32;

// G column-major (n x p). Returns false when no coefficients were found (d outside, or the
// solver gave up); xi gets p numbers in [-1, 1] either way.
bool zonotope_coefficients(const double* G, int n, int p, const double* d, double* xi);

}  // namespace marsyn::funnel
