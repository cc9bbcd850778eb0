#pragma once
// Is d in the zonotope {G xi : |xi|_inf <= 1}? A phase-1 simplex with bounded variables finds
// coefficients xi (n rows, p <= kMaxGenerators columns, dense, Bland's rule). Its answer is only
// a candidate: the controller accepts a state when the residual G xi - d of the clipped xi,
// evaluated in double, is within the stored tolerance, and the verification starts the next
// period from the zonotope grown by that tolerance and the residual's rounding (docs/soundness.md
// section 11), so a wrong or inaccurate solver answer can never let an unverified state in.
#include <vector>

namespace marsyn::funnel {

inline constexpr int kMaxMembershipGenerators = 64;
inline constexpr int kMaxMembershipRows = 32;

// G column-major (n x p). Returns false when no coefficients were found (d outside, or the
// solver gave up); xi gets p numbers in [-1, 1] either way.
bool zonotope_coefficients(const double* G, int n, int p, const double* d, double* xi);
// The same solver for any size, on the heap, with the most improving column entering (the
// soundness tests' reachable-set enclosures carry more generators than a stored set).
bool zonotope_coefficients_any(const double* G, int n, int p, const double* d, double* xi);

// A cheaper proposal first: the least-norm coefficients xi = P d with P = G' (G G')^-1 (p x n,
// row-major), computed once per set; empty when G G' is not safely positive definite. States
// near the centre, most of them, have these xi in the cube, and then no simplex is needed. Like
// the simplex's, these xi only propose: the controller's residual test decides.
std::vector<double> least_norm_map(const double* G, int n, int p);

// xi_j = sum_i P[j n + i] d_i, accumulated in i order (the exported C does the same operations).
inline void least_norm_coefficients(const double* P, int n, int p, const double* d, double* xi) {
  for (int j = 0; j < p; ++j) {
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += P[j * n + i] * d[i];
    xi[j] = s;
  }
}

}  // namespace marsyn::funnel
