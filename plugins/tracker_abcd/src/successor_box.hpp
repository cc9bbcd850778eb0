#pragma once
// Sound one-period successor boxes: for a box of initial states, a constant input u and every
// measurable disturbance with values in [-W, W], a box containing every state reachable after
// tau. The argument is in docs/soundness.md; the code follows it step by step.
#include <vector>

#include "marsyn/dynamics.hpp"
#include "marsyn/fast_interval.hpp"
#include "marsyn/interval.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn::abcd {

struct SuccessorOptions {
  double tau = 0.1;
  int substeps = 2;          // h = tau / substeps for the enclosure
  int taylor_terms = 10;     // terms of the matrix exponential series before the tail bound (<= 16)
  int picard_iterations = 12;
};

// Optional model-specific bound: marsyn::SuccessorBoundHook (tracker.hpp). Each successor box
// is the intersection of the generic box and the hook's box, so the hook can only tighten; it
// is tested with the same sampler (docs/soundness.md, "model hooks").
using SuccessorHook = marsyn::SuccessorBoundHook;

class SuccessorBox {
 public:
  SuccessorBox(const Dynamics& f, std::vector<double> w, SuccessorOptions opt, const SuccessorHook* hook = nullptr);

  // Returns false when no a priori enclosure was found (treat as "no successor": the input is
  // never used from this cell). lo/hi get n doubles each. Runs in round-to-nearest whatever the
  // caller's rounding mode, which is restored on return and on exceptions.
  bool compute(const Interval* cell, const double* u, double* lo, double* hi) const;

  // Between the samples: boxes[m * n + i] (m < substeps) encloses coordinate i of every state
  // the system can take during the m-th of `substeps` equal parts of the period, from any state
  // in `cell` with the constant input u and any disturbance (the a priori enclosures of the same
  // computation as compute(), docs/soundness.md "Continuous time"). False when no enclosure was
  // found or substeps is outside [1, kMaxEncloseSubsteps].
  static constexpr int kMaxEncloseSubsteps = 64;
  bool enclose(const Interval* cell, const double* u, int substeps, Interval* boxes) const;

  const SuccessorOptions& options() const { return opt_; }
  const Dynamics& dynamics() const { return f_; }
  const std::vector<double>& w() const { return w_; }

 private:
  // The substep loop shared by compute() and enclose(); C and beta as in docs/soundness.md §4,
  // apriori_boxes (substeps x n) receives each substep's a priori box when non-null.
  bool propagate(const Interval* cell, const double* u, int substeps, FastInterval* C, double* beta,
                 FastInterval* apriori_boxes) const;
  bool apriori(const FastInterval* x, const FastInterval* u, const FastInterval* w, const FastInterval& h,
               FastInterval* out) const;
  bool growth(const double* L, double* beta, double h_lo, double h_up) const;
  void jacobian(const FastInterval* x, const FastInterval* u, FastInterval* value, FastInterval* jac) const;

  const Dynamics& f_;
  int n_, m_;
  std::vector<double> w_;
  SuccessorOptions opt_;
  const SuccessorHook* hook_;
};

}  // namespace marsyn::abcd
