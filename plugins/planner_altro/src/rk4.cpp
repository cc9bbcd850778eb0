#include "rk4.hpp"

#include "marsyn/dual.hpp"
#include "marsyn/scalar.hpp"

namespace marsyn::altro {

namespace {

// S = d x / d(x0, u) (n x w) as the row-major A (n x n) and B (n x m).
void split(const double* S, int n, int m, int w, double* A, double* B) {
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) A[i * n + j] = S[i * w + j];
    for (int j = 0; j < m; ++j) B[i * m + j] = S[i * w + n + j];
  }
}

template <int NX, int W>
void staged_impl(const Dynamics& f, const double* x, const double* u, double tau, int substeps, double* A,
                 double* B, unsigned reads, double* Amid, double* Bmid, int mid) {
  const int n = NX > 0 ? NX : f.state_dim(), w = W > 0 ? W : f.state_dim() + f.input_dim(), m = w - n;
  // The state coordinates the field reads: f_x is zero in every other column, and two stage
  // points equal in these coordinates have the same field value and Jacobian (RK4 stages 2 and 3
  // of a field that ignores the coordinates its own rate moves, e.g. a unicycle's position).
  int dep[kMaxDual], nd = 0;
  for (int l = 0; l < n; ++l)
    if (reads >> l & 1u) dep[nd++] = l;
  double last[kMaxDual], last_k[kMaxDual];  // the last evaluated point and its field value
  bool have_last = false;
  // The field's dual arguments and results, per thread and kept from call to call: a DualD
  // zeroes all its kMaxDual slots on construction, which at every call cost more than the field
  // (sized to the model when it is known at compile time). The seeds (derivative 1 in their own
  // slot) are set when the width changes; a call writes only their values.
  constexpr int kN = NX > 0 ? NX : kMaxDual, kM = W > 0 ? (W - NX > 0 ? W - NX : 1) : kMaxDual;
  struct DualArgs {
    DualD yd[kN], ud[kM], kd[kN];
    int n = -1, w = -1;
  };
  static thread_local DualArgs args;
  DualArgs& da = args;
  if (da.n != n || da.w != w) {
    for (int i = 0; i < n; ++i) da.yd[i] = DualD::variable(0.0, i, w);
    for (int j = 0; j < m; ++j) da.ud[j] = DualD::variable(0.0, n + j, w);
    da.n = n;
    da.w = w;
  }
  DualD *yd = da.yd, *kd = da.kd;
  for (int j = 0; j < m; ++j) da.ud[j].v = u[j];
  double xs[kMaxDual], y[kMaxDual], kv[4][kMaxDual];
  // S = d xs / d(x0, u): n x w; dk[s] = d k_s / d(x0, u); Jf = [f_x f_u] at the stage point.
  double S[kMaxDual * kMaxDual], Y[kMaxDual * kMaxDual], dk[4][kMaxDual * kMaxDual], Jf[kMaxDual * kMaxDual];
  for (int i = 0; i < n; ++i) {
    xs[i] = x[i];
    for (int j = 0; j < w; ++j) S[i * w + j] = i == j ? 1.0 : 0.0;
  }
  const double h = tau / substeps;
  auto stage = [&](const double* pt, const double* dpt, int s) {
    bool same = have_last;
    for (int t = 0; t < nd && same; ++t) same = pt[dep[t]] == last[dep[t]];
    if (same) {
      for (int i = 0; i < n; ++i) kv[s][i] = last_k[i];  // and Jf is still that point's
    } else {
      for (int i = 0; i < n; ++i) yd[i].v = pt[i];
      f.field(yd, da.ud, kd);
      for (int i = 0; i < n; ++i) {
        kv[s][i] = kd[i].v;
        for (int j = 0; j < w; ++j) Jf[i * w + j] = kd[i].derivative(j);  // (kd outlives the call)
      }
      for (int t = 0; t < nd; ++t) last[dep[t]] = pt[dep[t]];
      for (int i = 0; i < n; ++i) last_k[i] = kv[s][i];
      have_last = true;
    }
    // dk = f_x * dpt + [0 f_u]
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < w; ++j) {
        double acc = j >= n ? Jf[i * w + j] : 0.0;
        for (int t = 0; t < nd; ++t) acc += Jf[i * w + dep[t]] * dpt[dep[t] * w + j];
        dk[s][i * w + j] = acc;
      }
  };
  for (int sub = 0; sub < substeps; ++sub) {
    stage(xs, S, 0);
    for (int i = 0; i < n; ++i) y[i] = xs[i] + (0.5 * h) * kv[0][i];
    for (int e = 0; e < n * w; ++e) Y[e] = S[e] + (0.5 * h) * dk[0][e];
    stage(y, Y, 1);
    for (int i = 0; i < n; ++i) y[i] = xs[i] + (0.5 * h) * kv[1][i];
    for (int e = 0; e < n * w; ++e) Y[e] = S[e] + (0.5 * h) * dk[1][e];
    stage(y, Y, 2);
    for (int i = 0; i < n; ++i) y[i] = xs[i] + h * kv[2][i];
    for (int e = 0; e < n * w; ++e) Y[e] = S[e] + h * dk[2][e];
    stage(y, Y, 3);
    for (int i = 0; i < n; ++i) xs[i] = xs[i] + (h / 6.0) * (kv[0][i] + 2.0 * kv[1][i] + 2.0 * kv[2][i] + kv[3][i]);
    for (int e = 0; e < n * w; ++e) S[e] = S[e] + (h / 6.0) * (dk[0][e] + 2.0 * dk[1][e] + 2.0 * dk[2][e] + dk[3][e]);
    if (Amid && sub + 1 == mid) split(S, n, m, w, Amid, Bmid);
  }
  split(S, n, m, w, A, B);
}

}  // namespace

// Forward-mode differentiation of the RK4 map done stage by stage: each stage needs only the
// field's own Jacobian [f_x f_u] (one dual evaluation), and the sensitivities are propagated with
// small dense products. Same derivative as marsyn::rk4_jacobians, without dual arithmetic in the
// stage combinations (which dominated the profile).
void rk4_jacobians_staged(const Dynamics& f, const double* x, const double* u, double tau, int substeps,
                          double* A, double* B, unsigned reads, double* Amid, double* Bmid, int mid) {
  const int n = f.state_dim(), m = f.input_dim();
  if (n == 3 && m == 2) return staged_impl<3, 5>(f, x, u, tau, substeps, A, B, reads, Amid, Bmid, mid);
  if (n == 2 && m == 1) return staged_impl<2, 3>(f, x, u, tau, substeps, A, B, reads, Amid, Bmid, mid);
  if (n == 4 && m == 1) return staged_impl<4, 5>(f, x, u, tau, substeps, A, B, reads, Amid, Bmid, mid);
  staged_impl<0, 0>(f, x, u, tau, substeps, A, B, reads, Amid, Bmid, mid);
}

KeptField::KeptField(const Dynamics& f, const double* u, unsigned reads) : f_(f), u_(u), n_(f.state_dim()) {
  for (int l = 0; l < n_ && l < kMaxDual; ++l)  // (larger models do not use it)
    if (reads >> l & 1u) dep_[nd_++] = l;
}

void KeptField::operator()(const double* pt, double* k) {
  bool same = have_;
  for (int t = 0; t < nd_ && same; ++t) same = pt[dep_[t]] == last_[dep_[t]];
  if (!same) {
    f_.field(pt, u_, last_k_);
    for (int t = 0; t < nd_; ++t) last_[dep_[t]] = pt[dep_[t]];
    have_ = true;
  }
  for (int i = 0; i < n_; ++i) k[i] = last_k_[i];
}

void rk4_step_kept(KeptField& field, int n, const double* x, double tau, int substeps, double* out, int steps) {
  double k1[kMaxDual], k2[kMaxDual], k3[kMaxDual], k4[kMaxDual], y[kMaxDual], xs[kMaxDual];
  for (int i = 0; i < n; ++i) xs[i] = x[i];
  const double h = tau / substeps;
  const int count = steps < 0 ? substeps : steps;
  for (int s = 0; s < count; ++s) {
    field(xs, k1);
    for (int i = 0; i < n; ++i) y[i] = xs[i] + (0.5 * h) * k1[i];
    field(y, k2);
    for (int i = 0; i < n; ++i) y[i] = xs[i] + (0.5 * h) * k2[i];
    field(y, k3);
    for (int i = 0; i < n; ++i) y[i] = xs[i] + h * k3[i];
    field(y, k4);
    for (int i = 0; i < n; ++i) xs[i] = xs[i] + (h / 6.0) * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  }
  for (int i = 0; i < n; ++i) out[i] = xs[i];
}

unsigned field_reads(const Dynamics& f) {
  const std::vector<bool> ignored = f.field_independent_of();
  unsigned reads = 0;
  for (int l = 0; l < f.state_dim() && l < kMaxDual; ++l)
    if (l >= static_cast<int>(ignored.size()) || !ignored[l]) reads |= 1u << l;
  return reads;
}

}  // namespace marsyn::altro
