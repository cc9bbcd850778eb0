#include "period_flow.hpp"

#include <algorithm>

#include "marsyn/apriori_enclosure.hpp"
#include "marsyn/scalar.hpp"

namespace marsyn::funnel {
namespace {

// Interval Jacobian of the state rows of F(z) = (f(x, u), 0) over the box (x, u), n x (n + m),
// and the interval value f(x, u).
void jacobian(const Dynamics& f, const FastInterval* x, const FastInterval* u, IMatrix& J, IVector& value) {
  const int n = f.state_dim(), m = f.input_dim(), N = n + m;
  std::vector<DualFI> xd(n), ud(m), out(n);
  for (int i = 0; i < n; ++i) xd[i] = DualFI::variable(x[i], i, N);
  for (int j = 0; j < m; ++j) ud[j] = DualFI::variable(u[j], n + j, N);
  f.field(xd.data(), ud.data(), out.data());
  J = IMatrix(n, N);
  value.resize(n);
  for (int i = 0; i < n; ++i) {
    value[i] = out[i].v;
    for (int k = 0; k < N; ++k) J(i, k) = out[i].derivative(k);
  }
}

bool finite(const FastInterval& x) { return std::isfinite(x.lower()) && std::isfinite(x.upper()); }

}  // namespace

FlowResult enclose_period(const Dynamics& f, const Zonotope& start, const std::vector<double>& w, int basis,
                          const FlowOptions& opt) {
  FlowResult r;
  const int n = f.state_dim(), m = f.input_dim(), N = n + m;
  if (start.dim() != N || static_cast<int>(w.size()) != n || opt.substeps < 1 || !(opt.tau > 0)) return r;
  const int S = opt.substeps;
  const int max_generators = std::max(opt.max_generators > 0 ? opt.max_generators : 3 * N, basis + N);
  const FastInterval h = FastInterval(opt.tau) / FastInterval(static_cast<double>(S));
  const FastInterval half_h2 = h * h / FastInterval(2.0);
  IVector W(n), X(N), B(n), FB, Fc(n), C(N), center(N);
  std::vector<double> hw(n);
  for (int i = 0; i < n; ++i) {
    W[i] = FastInterval(-w[i], w[i]);
    hw[i] = (h * FastInterval(w[i])).upper();
  }
  IMatrix JX, JB;
  IVector unused;
  Zonotope z = start;
  // Everything new within the period (rounding, wrapping, remainder, disturbance) is kept as one
  // box b, itself carried by |I + h Jm| each substep, and becomes generators at the period's end:
  // the generators stay few and are reduced once per period, not once per substep.
  std::vector<double> b(static_cast<std::size_t>(N), 0.0), nb(static_cast<std::size_t>(N)), radii;
  r.boxes.reserve(static_cast<std::size_t>(S) * n);
  for (int s = 0; s < S; ++s) {
    for (int i = 0; i < N; ++i) {
      X[i] = z.hull(i) + FastInterval(-b[i], b[i]);
      if (!finite(X[i])) return r;
    }
    const FastInterval* U = X.data() + n;
    // B holds every state over the substep, for every start in X, input in U and disturbance.
    if (!apriori_enclosure(f, X.data(), U, W.data(), h, opt.picard_iterations, B.data())) return r;
    for (int i = 0; i < n; ++i) r.boxes.push_back(B[i]);

    // x(t + h) = x + h f(x, u) + int_0^h (f(x(t+s), u) - f(x, u)) ds + int_0^h w ds. The middle
    // term is, row by row (mean value theorem on the segment, which B contains),
    // J_i(zeta) (x(t+s) - x) with x(t+s) - x in s (f(B, U) + W): it lies in h^2/2 [J](B)(f(B)+W).
    jacobian(f, B.data(), U, JB, FB);
    // The Euler part x + h f(x, u) over the zonotope, in mean-value form about its centre: the
    // midpoint Jacobian over the hull X acts on the generators, the rest of [J](X) is a box.
    jacobian(f, X.data(), U, JX, unused);
    for (int i = 0; i < N; ++i) C[i] = FastInterval(z.c[i]);
    f.field(C.data(), C.data() + n, Fc.data());
    std::vector<double> rad(N), extra(N, 0.0);
    for (int k = 0; k < N; ++k) rad[k] = fast_detail::add_up(z.radius(k), b[k]);
    Eigen::MatrixXd Jm(n, N);
    for (int i = 0; i < n; ++i) {
      FastInterval second(0.0), wrap(0.0);
      for (int k = 0; k < n; ++k) second += JB(i, k) * (FB[k] + W[k]);  // u' = 0: input columns add nothing
      for (int k = 0; k < N; ++k) {
        Jm(i, k) = median(JX(i, k));
        wrap += FastInterval(radius_about(JX(i, k), Jm(i, k))) * FastInterval(rad[k]);
      }
      center[i] = C[i] + h * Fc[i] + half_h2 * second;
      extra[i] = fast_detail::add_up((h * wrap).upper(), hw[i]);
      if (!finite(center[i]) || !std::isfinite(extra[i])) return r;
    }
    for (int i = n; i < N; ++i) center[i] = C[i];
    const int p = z.generators();
    IMatrix gens(N, p);
    for (int j = 0; j < p; ++j) {
      for (int i = 0; i < n; ++i) {
        FastInterval acc(0.0);
        for (int k = 0; k < N; ++k) acc += FastInterval(Jm(i, k)) * FastInterval(z.G(k, j));
        gens(i, j) = FastInterval(z.G(i, j)) + h * acc;
      }
      for (int i = n; i < N; ++i) gens(i, j) = FastInterval(z.G(i, j));
    }
    z = midpoints(center, gens, radii);
    for (int i = 0; i < N; ++i) {
      double carried = 0.0;
      if (i < n) {
        for (int k = 0; k < N; ++k)
          carried = fast_detail::add_up(carried, fast_detail::mul_up(mag(FastInterval(i == k ? 1.0 : 0.0) + h * FastInterval(Jm(i, k))), b[k]));
      } else {
        carried = b[i];  // u' = 0
      }
      nb[i] = fast_detail::add_up(fast_detail::add_up(carried, radii[i]), extra[i]);
      if (!std::isfinite(nb[i])) return r;
    }
    b.swap(nb);
  }
  append_box(z, b);
  reduce_order(z, basis, max_generators);
  r.end = std::move(z);
  r.ok = true;
  return r;
}

}  // namespace marsyn::funnel
