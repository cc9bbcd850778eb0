#pragma once
// The RK4 sampled map for the solver's inner loops: allocation-free states and exact Jacobians.
#include "marsyn/dynamics.hpp"

namespace marsyn::altro {

// Exact Jacobians of the RK4 map (row-major A: n x n, B: n x m), the derivative
// marsyn::rk4_jacobians computes, obtained stage by stage.
void rk4_jacobians_staged(const Dynamics& f, const double* x, const double* u, double tau, int substeps, double* A,
                          double* B);

}  // namespace marsyn::altro
