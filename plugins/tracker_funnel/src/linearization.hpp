#pragma once
// The Euler part of one enclosure step linearized about the centre c of the set, row by row:
// f_i(z) = f_i(c) + L_i (z - c) + e_i with |e_i| <= bound_i for every z with |z - c| <= rad
// (componentwise) inside the box X, z = (x, u). docs/soundness.md section 11 has the argument.
#include <vector>

#include <Eigen/Core>

#include "marsyn/dynamics.hpp"
#include "zonotope.hpp"

namespace marsyn::funnel {

struct Linearization {
  Eigen::MatrixXd L;           // n x (n + m), doubles
  std::vector<double> bound;   // n upper bounds; +inf where nothing finite was found
};

// Mean value: f_i(z) - f_i(c) = J_i(zeta)(z - c) with J_i(zeta) in [J_i](X); L_i is the midpoint
// of [J_i](X) and bound_i = |[J_i](X) - L_i| rad (the Jacobian's spread times the size).
Linearization mean_value_linearization(const Dynamics& f, const FastInterval* X, const std::vector<double>& rad);

// Second order: Taylor at c with the Lagrange remainder on the segment [c, z] (inside X):
// f_i(z) - f_i(c) = J_i(c)(z - c) + 1/2 (z - c)^T H_i(zeta)(z - c). L_i is the midpoint of the
// interval J_i(c) and bound_i = |J_i(c) - L_i| rad + scale/2 sum_jk |[H_i](X)|_jk rad_j rad_k
// (the size squared). scale is 1 except in tests showing they can fail. Needs
// f.has_interval_second_order(). c holds n + m point values.
Linearization second_order_linearization(const Dynamics& f, const FastInterval* X, const FastInterval* c,
                                         const std::vector<double>& rad, double scale = 1.0);

// Interval Hessians of the state rows over the box X: H[(i N + j) N + k] encloses
// d^2 f_i / dz_j dz_k (forward over forward on FastInterval, DualFI2); J the Jacobian over X.
void interval_hessian(const Dynamics& f, const FastInterval* X, IMatrix& J, std::vector<FastInterval>& H);

// The interval Jacobian of the state rows over X and the interval value f(X).
void interval_jacobian(const Dynamics& f, const FastInterval* X, IMatrix& J, IVector& value);

}  // namespace marsyn::funnel
