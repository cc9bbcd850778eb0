#pragma once
// The RK4 sampled map for the solver's inner loops: allocation-free states and exact Jacobians.
#include "marsyn/dynamics.hpp"

namespace marsyn::altro {

// Exact Jacobians of the RK4 map (row-major A: n x n, B: n x m), the derivative
// marsyn::rk4_jacobians computes, obtained stage by stage.
// reads: bit l set when the field reads state coordinate l (field_reads; default: all).
// Amid, Bmid (when non-null): the same Jacobians of the state after the first `mid` substeps, a
// by-product of the stage-by-stage sweep.
void rk4_jacobians_staged(const Dynamics& f, const double* x, const double* u, double tau, int substeps, double* A,
                          double* B, unsigned reads = ~0u, double* Amid = nullptr, double* Bmid = nullptr,
                          int mid = 0);

// The state coordinates f's field reads, as rk4_jacobians_staged's mask (from
// Dynamics::field_independent_of, which the dynamics tests check).
unsigned field_reads(const Dynamics& f);

}  // namespace marsyn::altro
