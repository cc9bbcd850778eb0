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

// One agent's field under a fixed input, with its last evaluation kept: a point equal to the
// last one (bit for bit) in the coordinates the field reads gets the last value again, which is
// what the field would return. A unicycle's RK4 stages 2 and 3 share their heading, so a
// rollout evaluates three fields per substep instead of four.
class KeptField {
 public:
  KeptField(const Dynamics& f, const double* u, unsigned reads);
  void operator()(const double* pt, double* k);

 private:
  const Dynamics& f_;
  const double* u_;
  int n_, nd_ = 0, dep_[kMaxDual];
  bool have_ = false;
  double last_[kMaxDual], last_k_[kMaxDual];
};

// rk4_step<double>'s arithmetic (no disturbance; the first `steps` substeps, all when < 0) with
// the fields from `field`: the same states bit for bit. n <= kMaxDual.
void rk4_step_kept(KeptField& field, int n, const double* x, double tau, int substeps, double* out, int steps = -1);

// The state coordinates f's field reads, as rk4_jacobians_staged's mask (from
// Dynamics::field_independent_of, which the dynamics tests check).
unsigned field_reads(const Dynamics& f);

}  // namespace marsyn::altro
