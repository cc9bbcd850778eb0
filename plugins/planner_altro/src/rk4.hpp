#pragma once
// The RK4 sampled map for the solver's inner loops: allocation-free states and exact Jacobians.
#include "marsyn/dynamics.hpp"

namespace marsyn::altro {

// marsyn::rk4_step<double> without its heap buffers (the rollouts call it T * N times per line
// search trial). The arithmetic is the same, operation for operation, so the exact check's
// re-simulation reproduces these states.
void rk4_step_fixed(const Dynamics& f, const double* x, const double* u, double tau, int substeps, double* out);

// Exact Jacobians of the RK4 map (row-major A: n x n, B: n x m), the derivative
// marsyn::rk4_jacobians computes, obtained stage by stage.
void rk4_jacobians_staged(const Dynamics& f, const double* x, const double* u, double tau, int substeps, double* A,
                          double* B);

}  // namespace marsyn::altro
