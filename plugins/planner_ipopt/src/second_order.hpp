#pragma once
// Second derivatives for the Hessian of the Lagrangian of the multiple-shooting NLP, block by
// block (docs/planners.md, ipopt section):
//  * exact, by forward-over-forward AD (marsyn::DualD2), for a dynamics block when the vector
//    field can be evaluated with DualD2, and by the constraint's own second derivative when a
//    constraint offers one;
//  * central differences of the exact AD first derivatives otherwise (and for `hessian:
//    differenced`).
// The detection below finds the second-order hooks of the plugin interfaces (Dynamics' DualD2
// field, Constraint::hessian) at compile time; a model or constraint may still decline at run
// time, and its block is then differenced.
#include <concepts>
#include <functional>

#include "marsyn/constraint.hpp"
#include "marsyn/dual.hpp"
#include "marsyn/dynamics.hpp"

namespace marsyn::ipopt_planner {

// One agent's vector field evaluated with nested duals; empty when it cannot be.
using SecondOrderField = std::function<void(const DualD2* x, const DualD2* u, DualD2* dx)>;

template <class D>
concept HasSecondOrderField = requires(const D& f, const DualD2* x, DualD2* dx) { f.field(x, x, dx); };

template <class D>
SecondOrderField second_order_field(const D& f) {
  if constexpr (HasSecondOrderField<D>) {
    // A Dynamics written by hand may not implement the overload (it would throw).
    if constexpr (requires { f.has_second_order(); })
      if (!f.has_second_order()) return {};
    return [&f](const DualD2* x, const DualD2* u, DualD2* dx) { f.field(x, u, dx); };
  } else {
    return {};
  }
}

// Sum over rows r of w[r] d^2 g_r / dx^2 on the support (row-major, added to H), when the
// constraint computes it; false otherwise.
template <class C>
concept HasConstraintHessian = requires(const C& c, const double* x, double* h) {
  { c.hessian(x, x, h) } -> std::convertible_to<bool>;
};

template <class C>
bool constraint_hessian(const C& c, const double* x, const double* w, double* H) {
  if constexpr (HasConstraintHessian<C>) {
    return c.hessian(x, w, H);
  } else {
    return false;
  }
}

inline bool interface_has_second_order_field() { return HasSecondOrderField<Dynamics>; }
inline bool interface_has_constraint_hessian() { return HasConstraintHessian<Constraint>; }

// H (w x w, w = n + m, row-major, overwritten) = sum_r lam[r] d^2 F_r / d(x, u)^2 for the RK4
// map F of `field` (the arithmetic of marsyn::rk4_step), exact by forward over forward AD.
void rk4_weighted_hessian(const SecondOrderField& field, int n, int m, const double* x, const double* u,
                          const double* lam, double tau, int substeps, double* H);

// The same block from central differences of the exact gradient lam' [A B] (marsyn::rk4_jacobians):
// error O(h^2) with h = 1e-5 max(1, |z|); symmetrized. Columns before `first` (x_0, fixed) are
// left at zero.
void differenced_dynamics_hessian(const Dynamics& f, const double* x, const double* u, const double* lam,
                                  double tau, int substeps, int first, double* H);

// sum_r w[r] d^2 g_r / dx^2 on the support of c (row-major, overwritten) from central
// differences of its exact Jacobian, symmetrized. `x` is the whole product state.
void differenced_constraint_hessian(const Constraint& c, const double* x, int n, const double* w, double* H);

}  // namespace marsyn::ipopt_planner
