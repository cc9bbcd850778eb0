#include "period_flow.hpp"

#include <algorithm>
#include <limits>

#include "marsyn/apriori_enclosure.hpp"
#include "linearization.hpp"
#include "marsyn/scalar.hpp"

namespace marsyn::funnel {
namespace {

// Interval Jacobian of the state rows of F(z) = (f(x, u), 0) over the box (x, u), n x (n + m),
// and the interval value f(x, u).
void jacobian(const Dynamics& f, const FastInterval* x, const FastInterval* u, IMatrix& J, IVector& value) {
  const int n = f.state_dim(), m = f.input_dim();
  std::vector<FastInterval> X(x, x + n);
  X.insert(X.end(), u, u + m);
  interval_jacobian(f, X.data(), J, value);
}

bool finite(const FastInterval& x) { return std::isfinite(x.lower()) && std::isfinite(x.upper()); }

}  // namespace

// One interval per dot product instead of one interval product per term (the enclosure's
// generator product, most of a 12-state funnel's time): s, the round-to-nearest sum, and
// |s - exact| <= gamma_N sum_k |a_k b_k| in any order of summation, an FMA's single rounding
// included (Higham, Accuracy and Stability of Numerical Algorithms, section 3.1),
// gamma_N = N u / (1 - N u), u = 2^-53; the sum of magnitudes t is
// itself a round-to-nearest sum, so sum |a_k b_k| <= t / (1 - gamma_N) and the error is at most
// gamma_N / (1 - gamma_N) t <= 2 N u t (N u <= 1/4). The relative bound fails only where a
// product underflows, by at most half the smallest subnormal each: N + 1 of them are added.
// docs/soundness.md, section 2.
FastInterval dot_enclosure(const double* a, const double* b, std::ptrdiff_t b_stride, int N) {
  double s = 0.0, t = 0.0;
  for (int k = 0; k < N; ++k) {
    const double p = a[k] * b[k * b_stride];
    s += p;
    t += std::fabs(p);
  }
  constexpr double inf = std::numeric_limits<double>::infinity();
  if (!std::isfinite(s) || !std::isfinite(t)) return FastInterval(-inf, inf);
  const double c = static_cast<double>(N) * 0x1p-52;  // 2 N u, exact
  const double e = fast_detail::add_up(fast_detail::mul_up(c, t), static_cast<double>(N + 1) * std::numeric_limits<double>::denorm_min());
  return FastInterval(fast_detail::sub_down(s, e), fast_detail::add_up(s, e));
}

namespace {

// The a priori box B of one substep under W(x, u): W taken over the start box X, then over B
// grown by a hair, until W over that neighbourhood of B lies within the W that B was computed
// with. Then no solution leaves B: up to a first exit from the neighbourhood, w(t) lies in the W
// used, so the solution is one of the box's and stays in B, strictly inside the neighbourhood
// (docs/soundness.md section 12). `w` gets the W used, `W` the same as intervals, `hw` h w rounded
// up. A constant W is the a priori box alone.
bool substep_box(const Dynamics& f, const DisturbanceBound& dist, const FastInterval* X, const FastInterval* U,
                 const FastInterval& h, int iterations, std::vector<double>& w, IVector& W, std::vector<double>& hw,
                 FastInterval* B) {
  if (dist.constant()) return apriori_enclosure(f, X, U, W.data(), h, iterations, B);
  const int n = f.state_dim();
  auto settle = [&] {
    for (int i = 0; i < n; ++i) hw[static_cast<std::size_t>(i)] = (h * FastInterval(w[static_cast<std::size_t>(i)])).upper();
    return true;
  };
  std::vector<double> next(static_cast<std::size_t>(n));
  std::vector<FastInterval> grown(static_cast<std::size_t>(n));
  auto hair = [](const FastInterval& b) {
    const double r = fast_detail::add_up(fast_detail::mul_up(1e-9, mag(b)), 1e-300);
    return FastInterval(fast_detail::sub_down(b.lower(), r), fast_detail::add_up(b.upper(), r));
  };
  for (int i = 0; i < n; ++i) grown[static_cast<std::size_t>(i)] = hair(X[i]);
  dist.sup(grown.data(), U, w.data());
  for (int attempt = 0; attempt < 8; ++attempt) {
    for (int i = 0; i < n; ++i) W[i] = FastInterval(-w[static_cast<std::size_t>(i)], w[static_cast<std::size_t>(i)]);
    if (!apriori_enclosure(f, X, U, W.data(), h, iterations, B)) return false;
    for (int i = 0; i < n; ++i) grown[static_cast<std::size_t>(i)] = hair(B[i]);
    dist.sup(grown.data(), U, next.data());
    bool inside = true;
    for (int i = 0; i < n; ++i)
      if (!(next[static_cast<std::size_t>(i)] <= w[static_cast<std::size_t>(i)])) inside = false;
    if (inside) return settle();
    // A little more than asked, so that the next box's W settles inside it.
    for (int i = 0; i < n; ++i)
      w[static_cast<std::size_t>(i)] = std::max(w[static_cast<std::size_t>(i)],
                                                fast_detail::mul_up(next[static_cast<std::size_t>(i)], 1.0 + 1e-6));
  }
  return false;
}

}  // namespace

FlowResult enclose_period(const Dynamics& f, const Zonotope& start, const std::vector<double>& w, int basis,
                          const FlowOptions& opt) {
  return enclose_period(f, start, DisturbanceBound(w), basis, opt);
}

FlowResult enclose_period(const Dynamics& f, const Zonotope& start, const DisturbanceBound& dist, int basis,
                          const FlowOptions& opt) {
  FlowResult r;
  const int n = f.state_dim(), m = f.input_dim(), N = n + m;
  if (start.dim() != N || dist.dim() != n || opt.substeps < 1 || !(opt.tau > 0)) return r;
  std::vector<double> w = dist.base();
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
  IMatrix JB;
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
    if (!substep_box(f, dist, X.data(), U, h, opt.picard_iterations, w, W, hw, B.data())) return r;
    for (int i = 0; i < n; ++i) r.boxes.push_back(B[i]);

    // x(t + h) = x + h f(x, u) + int_0^h (f(x(t+s), u) - f(x, u)) ds + int_0^h w ds. The middle
    // term is, row by row (mean value theorem on the segment, which B contains),
    // J_i(zeta) (x(t+s) - x) with x(t+s) - x in s (f(B, U) + W): it lies in h^2/2 [J](B)(f(B)+W).
    jacobian(f, B.data(), U, JB, FB);
    // The Euler part x + h f(x, u) over the zonotope z (plus the box b), row by row, about its
    // centre c: f_i(z) = f_i(c) + L_i (z - c) + e_i with |e_i| <= bound_i (linearization.hpp),
    // from the mean-value form and, when the model has interval Hessians, the second-order form.
    // Either statement holds for row i alone, so each row keeps the smaller bound.
    for (int i = 0; i < N; ++i) C[i] = FastInterval(z.c[i]);
    std::vector<double> rad(N), extra(N, 0.0);
    for (int k = 0; k < N; ++k) rad[k] = fast_detail::add_up(z.radius(k), b[k]);
    const Linearization mv = mean_value_linearization(f, X.data(), rad);
    const bool second_order = opt.remainder == Remainder::SecondOrder && f.has_interval_second_order();
    Linearization so;
    if (second_order) so = second_order_linearization(f, X.data(), C.data(), rad, opt.remainder_scale);
    f.field(C.data(), C.data() + n, Fc.data());
    Eigen::MatrixXd Jm(n, N);
    r.rows += n;
    for (int i = 0; i < n; ++i) {
      FastInterval second(0.0);
      for (int k = 0; k < n; ++k) second += JB(i, k) * (FB[k] + W[k]);  // u' = 0: input columns add nothing
      const bool use_so = second_order && so.bound[i] < mv.bound[i];
      const Linearization& lin = use_so ? so : mv;
      if (use_so) ++r.second_order_rows;
      Jm.row(i) = lin.L.row(i);
      center[i] = C[i] + h * Fc[i] + half_h2 * second;
      extra[i] = fast_detail::add_up((h * FastInterval(lin.bound[i])).upper(), hw[i]);
      if (!finite(center[i]) || !std::isfinite(extra[i])) return r;
    }
    for (int i = n; i < N; ++i) center[i] = C[i];
    const int p = z.generators();
    IMatrix gens(N, p);
    const Eigen::MatrixXd JmT = Jm.transpose();  // row i of Jm contiguous
    for (int j = 0; j < p; ++j) {
      const double* g = &z.G(0, j);
      for (int i = 0; i < n; ++i)
        gens(i, j) = FastInterval(z.G(i, j)) + h * dot_enclosure(JmT.col(i).data(), g, 1, N);
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
    if (opt.box_substeps > 0 && (s + 1) % opt.box_substeps == 0 && s + 1 < S) {
      // The same set: each box coordinate gets a generator of its own coefficient.
      append_box(z, b);
      std::fill(b.begin(), b.end(), 0.0);
      reduce_order(z, basis, max_generators);
    }
  }
  append_box(z, b);
  reduce_order(z, basis, max_generators);
  r.end = std::move(z);
  r.ok = true;
  return r;
}

}  // namespace marsyn::funnel
