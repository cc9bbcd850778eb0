#include "successor_box.hpp"

#include <algorithm>
#include <cfenv>
#include <cmath>
#include <stdexcept>

#include "uniform_grid.hpp"

namespace marsyn::abcd {
namespace {

// The series below sums non-negative terms with the FPU rounding upward (section 4c of
// docs/soundness.md); nothing in that block calls libm or an interval operation. The previous
// mode comes back on every exit path.
class UpwardScope {
 public:
  UpwardScope() : saved_(std::fegetround()) { std::fesetround(FE_UPWARD); }
  ~UpwardScope() { std::fesetround(saved_); }
  UpwardScope(const UpwardScope&) = delete;
  UpwardScope& operator=(const UpwardScope&) = delete;

 private:
  int saved_;
};

}  // namespace

SuccessorBox::SuccessorBox(const Dynamics& f, std::vector<double> w, SuccessorOptions opt, const SuccessorHook* hook)
    : f_(f), n_(f.state_dim()), m_(f.input_dim()), w_(std::move(w)), opt_(opt), hook_(hook) {
  if (n_ < 1 || n_ > kMaxDim || m_ < 1 || m_ > kMaxDim || n_ + m_ > kMaxDual)
    throw std::invalid_argument("successor box: unsupported state/input dimension");
  if (static_cast<int>(w_.size()) != n_) throw std::invalid_argument("successor box: W must have the state dimension");
  for (double v : w_)
    if (!(v >= 0) || !std::isfinite(v)) throw std::invalid_argument("successor box: W must be non-negative");
  if (!(opt_.tau > 0) || opt_.substeps < 1 || opt_.taylor_terms < 2 || opt_.taylor_terms > 16 || opt_.picard_iterations < 1)
    throw std::invalid_argument("successor box: bad options");
}

// Picard a priori enclosure over one substep. If X + [0, h] (F(B, u) + W) is contained in B,
// every solution from X stays in that candidate over [0, h] (Schauder fixed point on C([0,h], B)
// and uniqueness for a locally Lipschitz field with a measurable disturbance).
bool SuccessorBox::apriori(const FastInterval* x, const FastInterval* u, const FastInterval* w, const FastInterval& h,
                           FastInterval* out) const {
  const FastInterval t(0.0, h.upper());
  FastInterval b[kMaxDim], fb[kMaxDim], cand[kMaxDim];
  f_.field(x, u, fb);
  for (int i = 0; i < n_; ++i) b[i] = x[i] + t * (fb[i] + w[i]);
  for (int it = 0; it < opt_.picard_iterations; ++it) {
    // Inflation makes the containment test succeed after a few rounds for a smooth field.
    for (int i = 0; i < n_; ++i) {
      const double r = 0.1 * width(b[i]) + 1e-12 * (1.0 + mag(b[i]));
      b[i] = FastInterval(b[i].lower() - r, b[i].upper() + r);
      if (!std::isfinite(b[i].lower()) || !std::isfinite(b[i].upper())) return false;
    }
    f_.field(b, u, fb);
    bool inside = true;
    for (int i = 0; i < n_; ++i) {
      cand[i] = x[i] + t * (fb[i] + w[i]);
      // An interval with a NaN bound is empty (hence a subset of anything) and an infinite one
      // bounds nothing: reject non-finite candidates explicitly.
      if (!std::isfinite(cand[i].lower()) || !std::isfinite(cand[i].upper())) return false;
      if (!subset(cand[i], b[i])) inside = false;
    }
    if (inside) {
      for (int i = 0; i < n_; ++i) out[i] = cand[i];
      return true;
    }
    for (int i = 0; i < n_; ++i) b[i] = hull(b[i], cand[i]);
  }
  return false;
}

void SuccessorBox::jacobian(const FastInterval* x, const FastInterval* u, FastInterval* value, FastInterval* jac) const {
  DualFI xd[kMaxDim], ud[kMaxDim], out[kMaxDim];
  for (int i = 0; i < n_; ++i) xd[i] = DualFI::variable(x[i], i, n_);
  for (int j = 0; j < m_; ++j) ud[j] = DualFI(u[j]);
  f_.field(xd, ud, out);
  for (int i = 0; i < n_; ++i) {
    if (value) value[i] = out[i].v;
    for (int j = 0; j < n_; ++j) jac[i * n_ + j] = out[i].derivative(j);
  }
}

// beta <- e^{Lh} beta + int_0^h e^{Ls} ds W for a Metzler L. With c = max(0, -min L_ii) the
// matrix M = (L + cI) h is non-negative, e^{Lh} = e^{-ch} e^{M} and the integral is at most
// h e^{M}-series with 1/(k+1)! weights (e^{-cs} <= 1), so every term is a non-negative sum of
// products: computed once with the FPU rounding upward they are upper bounds, without an
// interval operation (and its two rounding-mode switches) per term. Tails beyond K terms are
// bounded by ||M||^{K+1}/(K+1)! / (1 - ||M||/(K+2)) in the infinity norm.
bool SuccessorBox::growth(const double* L, double* beta, double h_lo, double h_up) const {
  const int n = n_, K = opt_.taylor_terms;
  double c = 0.0;
  for (int i = 0; i < n; ++i) c = std::max(c, -L[i * n + i]);
  // exp(-c h) rounded up: libm exp (called in round-to-nearest) is within 2 ulp;
  // detail::widen_up adds a 4 ulp margin. -c h is rounded up as -(c h rounded down).
  const double decay = c > 0 ? std::min(1.0, detail::widen_up(std::exp(-fast_detail::mul_down(c, h_lo)))) : 1.0;
  const UpwardScope upward;
  double M[kMaxDim * kMaxDim], norm = 0.0;
  for (int i = 0; i < n; ++i) {
    double row = 0.0;
    for (int j = 0; j < n; ++j) {
      const double l = (i == j) ? L[i * n + j] + c : L[i * n + j];
      M[i * n + j] = std::max(0.0, l) * h_up;
      row += M[i * n + j];
    }
    norm = std::max(norm, row);
  }
  bool ok = norm < K + 2 && std::isfinite(norm);
  double tb[kMaxDim], tw[kMaxDim], ab[kMaxDim], aw[kMaxDim], nb[kMaxDim], nw[kMaxDim];
  double bmax = 0.0, wmax = 0.0;
  for (int i = 0; i < n; ++i) {
    tb[i] = ab[i] = beta[i];
    tw[i] = aw[i] = h_up * w_[i];
    bmax = std::max(bmax, beta[i]);
    wmax = std::max(wmax, w_[i]);
  }
  for (int k = 1; ok && k <= K; ++k) {
    for (int i = 0; i < n; ++i) {
      double sb = 0.0, sw = 0.0;
      for (int j = 0; j < n; ++j) {
        sb += M[i * n + j] * tb[j];
        sw += M[i * n + j] * tw[j];
      }
      nb[i] = sb / k;
      nw[i] = sw / (k + 1);
    }
    for (int i = 0; i < n; ++i) {
      tb[i] = nb[i];
      tw[i] = nw[i];
      ab[i] += nb[i];
      aw[i] += nw[i];
    }
  }
  if (ok) {
    double pw = 1.0, fact = 1.0;
    for (int k = 1; k <= K + 1; ++k) {
      pw *= norm;
      fact *= k;
    }
    // 1/(1 - a/b) rounded up: compute the denominator rounded down as -((a/b) - 1) with upward
    // rounding of a/b.
    const double den_e = -((norm / (K + 2)) - 1.0), den_g = -((norm / (K + 3)) - 1.0);
    ok = den_e > 0 && den_g > 0;
    if (ok) {
      // pw is rounded up; dividing needs the factorials exact: (K+2)! < 2^53 for K <= 16, so
      // every partial product is an exactly representable integer.
      const double tail_e = pw / fact / den_e;
      const double tail_g = h_up * pw / (fact * (K + 2)) / den_g;
      const double tail = tail_e * bmax + tail_g * wmax;
      for (int i = 0; i < n; ++i) beta[i] = decay * ab[i] + aw[i] + tail;
    }
  }
  return ok;
}

bool SuccessorBox::propagate(const Interval* cell, const double* u, int substeps, FastInterval* C, double* beta,
                             FastInterval* apriori_boxes) const {
  const int n = n_;
  FastInterval U[kMaxDim], W[kMaxDim];
  for (int j = 0; j < m_; ++j) U[j] = FastInterval(u[j]);
  for (int i = 0; i < n; ++i) {
    W[i] = FastInterval(-w_[i], w_[i]);
  }
  // C encloses the disturbance-free solution from the cell's centre c; beta bounds every true
  // state's distance to it.
  for (int i = 0; i < n; ++i) {
    const FastInterval ci(cell[i]);
    const double c = median(ci);
    C[i] = FastInterval(c);
    const FastInterval d = ci - C[i];
    beta[i] = mag(d);
  }
  const FastInterval h = FastInterval(opt_.tau) / FastInterval(static_cast<double>(substeps));
  const FastInterval half_h2 = h * h / FastInterval(2.0);
  FastInterval X[kMaxDim], B[kMaxDim], Fc[kMaxDim], FC[kMaxDim], J[kMaxDim * kMaxDim], next[kMaxDim];
  for (int s = 0; s < substeps; ++s) {
    for (int i = 0; i < n; ++i) X[i] = C[i] + FastInterval(-beta[i], beta[i]);
    if (!apriori(X, U, W, h, B)) return false;
    // B holds every true state over the substep (docs/soundness.md, "Continuous time").
    if (apriori_boxes)
      for (int i = 0; i < n; ++i) apriori_boxes[s * n + i] = B[i];

    // One Jacobian enclosure over B serves both halves: B holds every true trajectory and, as
    // w = 0 is admissible and C lies in X, the centre trajectory too.
    jacobian(B, U, Fc, J);

    // Centre: x(h) = x + h f(x) + h^2/2 x''(xi) per component, x'' = Df f along the centre
    // trajectory, which stays in B.
    f_.field(C, U, FC);
    for (int i = 0; i < n; ++i) {
      FastInterval xdd(0.0);
      for (int j = 0; j < n; ++j) xdd += J[i * n + j] * Fc[j];
      next[i] = C[i] + h * FC[i] + half_h2 * xdd;
    }

    // Deviation (growth bound): L is a Metzler upper bound of Df over B, which holds both the
    // true and the centre trajectory; beta' = e^{Lh} beta + int_0^h e^{Ls} ds W.
    double L[kMaxDim * kMaxDim];
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        L[i * n + j] = (i == j) ? J[i * n + j].upper() : mag(J[i * n + j]);
        if (!std::isfinite(L[i * n + j])) return false;
      }
    if (!growth(L, beta, h.lower(), h.upper())) return false;
    for (int i = 0; i < n; ++i) C[i] = next[i];
  }
  return true;
}

bool SuccessorBox::compute(const Interval* cell, const double* u, double* lo, double* hi) const {
  // FastInterval's error-free transformations need round-to-nearest; so does every plain double
  // operation here and in the model's field (constants, libm calls), as in a double evaluation.
  const RoundToNearestScope nearest;
  const int n = n_;
  FastInterval C[kMaxDim];
  double beta[kMaxDim];
  if (!propagate(cell, u, opt_.substeps, C, beta, nullptr)) return false;
  for (int i = 0; i < n; ++i) {
    lo[i] = (C[i] - FastInterval(beta[i])).lower();
    hi[i] = (C[i] + FastInterval(beta[i])).upper();
    if (!std::isfinite(lo[i]) || !std::isfinite(hi[i])) return false;
  }
  if (hook_) {
    double hl[kMaxDim], hh[kMaxDim];
    if (hook_->successor(cell, u, w_.data(), opt_.tau, hl, hh)) {
      for (int i = 0; i < n; ++i) {
        lo[i] = std::max(lo[i], hl[i]);
        hi[i] = std::min(hi[i], hh[i]);
      }
    }
  }
  return true;
}

bool SuccessorBox::enclose(const Interval* cell, const double* u, int substeps, Interval* boxes) const {
  if (substeps < 1 || substeps > kMaxEncloseSubsteps) return false;
  FastInterval C[kMaxDim], B[kMaxEncloseSubsteps * kMaxDim];
  double beta[kMaxDim];
  {
    const RoundToNearestScope nearest;
    if (!propagate(cell, u, substeps, C, beta, B)) return false;
    for (int k = 0; k < substeps * n_; ++k)
      if (!std::isfinite(B[k].lower()) || !std::isfinite(B[k].upper())) return false;
  }
  for (int k = 0; k < substeps * n_; ++k) boxes[k] = Interval(B[k].lower(), B[k].upper());
  return true;
}

}  // namespace marsyn::abcd
