// `marsyn export --format c` for a funnel controller: const tables (x_k, u_k, K_k, the verified
// sets V_k) and two functions, `<prefix>_input` and the monitor `<prefix>_inside`.
//
// Bit-identity with FunnelController (funnel_controller.cpp, membership.cpp): the C performs the
// same IEEE double operations on the same doubles in the same order, so nothing is re-derived:
// - every constant is a hexadecimal floating literal, the very double of the .ctrl file;
// - u = clamp(u_k + sum_j K_ij (x_j - x_kj)) is accumulated left to right from u_k, as the C++
//   loop does, and clamped with std::clamp's comparisons;
// - the set tests are in_set's loops; the zonotope's least-norm map P is stored (the doubles
//   FunnelController computes from the same G) and its coefficients tried first in the same
//   order; the membership solver is membership.cpp's simplex transcribed operation by operation (its answer only proposes coefficients; the
//   residual test decides, so even a solver that differed could only refuse, never accept, a
//   state outside the verified zonotope: docs/soundness.md section 11);
// - the source refuses excess precision and turns contraction into FMA off (c_source.hpp).
#include "export_c.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "marsyn/c_source.hpp"
#include "membership.hpp"

namespace marsyn::funnel {
namespace {

using c_source::array_body;
using c_source::array_body_2d;
using c_source::hex_double;

int unsigned_bytes(unsigned long long v) { return v <= 0xFFull ? 1 : v <= 0xFFFFull ? 2 : 4; }

// box_k's bounds as eps_box (funnel_synthesis.cpp) computes them with directed rounding, here
// with round-to-nearest operations only (the C target may have no rounding modes): the rounding
// error of a - b, or a + b, is exact by TwoSum, and a step to the neighbouring double is
// t +- phi |t| with phi = 2^-53 (1 + 2^-52) (Rump, Zimmermann, Boldo, Melquiond 2009). Used only
// where it gives the stored bound's very bits (checked per step at export), so the C's box test
// is the C++ one.
double up_difference(double a, double b) {
  const double t = a - b, bb = t - a, e = (a - (t - bb)) + (-b - bb);
  return e > 0.0 ? t + 0x1.0000000000001p-53 * std::fabs(t) : t;
}
double down_sum(double a, double b) {
  const double t = a + b, bb = t - a, e = (a - (t - bb)) + (b - bb);
  return e < 0.0 ? t - 0x1.0000000000001p-53 * std::fabs(t) : t;
}
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The C's set kinds: the file's (0 box, 1 parallelotope, 2 zonotope), 3 for a zonotope whose
// last n generators are the coordinate axes scaled (G = [G' | diag(r)], every other entry of
// those columns +0.0, as Girard's reduction leaves them: stored as r, not n x n), plus
// kExplicitBox when box_k is not x_k +- eps rounded inward (the initial box).
constexpr int kAxisZonotope = 3, kExplicitBox = 4;

bool axis_tail(const StepSet& s, int n) {
  if (s.kind != kZonotope || s.generators < n) return false;
  const int first = s.generators - n;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double v = s.S[static_cast<size_t>((first + j) * n + i)];
      if (i == j ? v == 0.0 : !same_bits(v, 0.0)) return false;
    }
  return true;
}

bool eps_box_of(const FunnelData& d, int k) {
  const StepSet& s = d.sets[static_cast<size_t>(k)];
  for (int i = 0; i < d.n; ++i) {
    const double x = d.x_nom[static_cast<size_t>(k)][static_cast<size_t>(i)], e = d.eps[static_cast<size_t>(i)];
    if (!same_bits(up_difference(x, e), s.lo[static_cast<size_t>(i)]) || !same_bits(down_sum(x, e), s.hi[static_cast<size_t>(i)]))
      return false;
  }
  return true;
}

// Per step the C kind and the numbers it needs in one pool, each step's at an offset: explicit
// box lo, hi; then c and S (kind 1), c, G and tol (kind 2) or c, G', r and tol (kind 3).
struct SetPool {
  std::vector<double> values;
  std::vector<unsigned long long> at;  // T + 1
  std::vector<int> kind;               // T + 1, C kinds
  int max_generators = 0;
  bool any_zonotope = false, any_parallelotope = false, any_axis = false;
  int offset_bytes = 1;
  // The zonotopes' least-norm maps (membership.hpp), each step's at fast_at[k] (-1: none), as
  // FunnelController computes them from the same G.
  std::vector<double> fast;
  std::vector<long long> fast_at;  // T + 1
};

SetPool pool_of(const FunnelData& d) {
  SetPool p;
  const int n = d.n;
  for (int k = 0; k <= d.horizon(); ++k) {
    const StepSet& s = d.sets[static_cast<size_t>(k)];
    p.at.push_back(p.values.size());
    int kind = s.kind;
    if (!eps_box_of(d, k)) {
      kind |= kExplicitBox;
      p.values.insert(p.values.end(), s.lo.begin(), s.lo.end());
      p.values.insert(p.values.end(), s.hi.begin(), s.hi.end());
    }
    if (s.kind != kBox) p.values.insert(p.values.end(), s.c.begin(), s.c.end());
    if (s.kind == kParallelotope) {
      p.values.insert(p.values.end(), s.S.begin(), s.S.end());
      p.any_parallelotope = true;
    } else if (s.kind == kZonotope) {
      const bool axis = axis_tail(s, n);
      const int dense = axis ? s.generators - n : s.generators;
      p.values.insert(p.values.end(), s.S.begin(), s.S.begin() + static_cast<long>(dense) * n);
      for (int j = 0; axis && j < n; ++j) p.values.push_back(s.S[static_cast<size_t>((dense + j) * n + j)]);
      p.values.insert(p.values.end(), s.tol.begin(), s.tol.end());
      p.max_generators = std::max(p.max_generators, s.generators);
      p.any_zonotope = true;
      const std::vector<double> P = least_norm_map(s.S.data(), n, s.generators);
      p.fast_at.push_back(P.empty() ? -1 : static_cast<long long>(p.fast.size()));
      p.fast.insert(p.fast.end(), P.begin(), P.end());
      p.any_axis = p.any_axis || axis;
      if (axis) kind = (kind & kExplicitBox) | kAxisZonotope;
    }
    if (s.kind != kZonotope) p.fast_at.push_back(-1);
    p.kind.push_back(kind);
  }
  p.offset_bytes = unsigned_bytes(p.values.size());
  return p;
}

// x_k (k <= T), u_k, K_k, eps, u_lo, u_hi and the pool (doubles); kind and generators (u8) and
// the pool's offsets per step.
long long const_bytes(const FunnelData& d, const SetPool& p) {
  const long long T = d.horizon(), n = d.n, m = d.m;
  const long long doubles = (T + 1) * n + T * (m + m * n) + n + 2 * m + std::max<long long>(1, static_cast<long long>(p.values.size()));
  return 8 * (doubles + static_cast<long long>(p.fast.size())) +
         (T + 1) * (1 + (p.any_zonotope ? 1 + 4 : 0) + p.offset_bytes);
}

// membership.cpp's zonotope_coefficients for this agent's n (rows) and largest p, with fixed-size
// arrays: the same operations in the same order. At most 50 (n + p) + 100 pivots.
void write_solver(std::ostream& c, const std::string& p, int n, int pmax) {
  c << "/* Coefficients xi in [-1, 1]^g with G xi = d when the solver finds them: marsyn's membership solver\n"
       " * (a phase-1 simplex with bounded variables, Bland's rule), operation by operation. Only a\n"
       " * proposal: " << p << "inside() accepts x only if the residual of these xi is within tol.\n"
       " * Worst case: 50 (n + g) + 100 = " << 50 * (n + pmax) + 100 << " pivots of O(n (n + g)) each; stack "
    << 8 * (n * (pmax + n) + n) + 2 * (pmax + n) + 4 * n << " bytes. */\n"
    << "#define " << p << "ROWS " << n << "\n#define " << p << "GMAX " << pmax << "\n"
    << "static void " << p << "coefficients(const double *G, int g, const double *d, double *xi)\n{\n"
    << "  double tableau[" << p << "ROWS][" << p << "GMAX + " << p << "ROWS], value[" << p << "ROWS], scale = 0.0, tol, pivot_tol;\n"
    << "  int basis[" << p << "ROWS], i, j, it, max_iterations;\n"
    << "  unsigned char at_upper[" << p << "GMAX + " << p << "ROWS], is_basic[" << p << "GMAX + " << p << "ROWS];\n"
    << "  const int cols = g + " << p << "ROWS;\n"
    << "  for (j = 0; j < g; ++j)\n    xi[j] = 0.0;\n"
    << "  for (j = 0; j < cols; ++j) {\n    at_upper[j] = 0;\n    is_basic[j] = 0;\n"
    << "    for (i = 0; i < " << p << "ROWS; ++i)\n      tableau[i][j] = 0.0;\n  }\n"
    << "  for (i = 0; i < " << p << "ROWS; ++i) {\n"
    << "    double rhs = d[i], s;\n"
    << "    for (j = 0; j < g; ++j) {\n      rhs += G[i + j * " << p << "ROWS];\n"
    << "      if (scale < fabs(G[i + j * " << p << "ROWS]))\n        scale = fabs(G[i + j * " << p << "ROWS]);\n    }\n"
    << "    if (scale < fabs(d[i]))\n      scale = fabs(d[i]);\n"
    << "    s = rhs >= 0 ? 1.0 : -1.0;\n"
    << "    for (j = 0; j < g; ++j)\n      tableau[i][j] = s * G[i + j * " << p << "ROWS];\n"
    << "    tableau[i][g + i] = 1.0;\n    value[i] = fabs(rhs);\n    basis[i] = g + i;\n    is_basic[g + i] = 1;\n  }\n"
    << "  if (!(scale > 0.0 && scale <= DBL_MAX))\n    return;\n"
    << "  tol = 1e-11 * scale;\n  pivot_tol = 1e-9 * scale;\n"
    << "  max_iterations = 50 * (" << p << "ROWS + g) + 100;\n"
    << "  for (it = 0; it < max_iterations; ++it) {\n"
    << "    int enter = -1, leave = -1, out;\n"
    << "    double dir = 0.0, theta = 2.0, piv, entering_value;\n"
    << "    unsigned char leave_to_upper = 0;\n"
    << "    for (j = 0; j < g && enter < 0; ++j) {\n"
    << "      double r = 0.0;\n"
    << "      if (is_basic[j])\n        continue;\n"
    << "      for (i = 0; i < " << p << "ROWS; ++i)\n        if (basis[i] >= g)\n          r -= tableau[i][j];\n"
    << "      if (!at_upper[j] && r < -tol) {\n        enter = j;\n        dir = 1.0;\n"
    << "      } else if (at_upper[j] && r > tol) {\n        enter = j;\n        dir = -1.0;\n      }\n    }\n"
    << "    if (enter < 0)\n      break;\n"
    << "    for (i = 0; i < " << p << "ROWS; ++i) {\n"
    << "      const double a = dir * tableau[i][enter];\n      double limit;\n      unsigned char to_upper = 0;\n"
    << "      if (a > pivot_tol) {\n        limit = value[i] / a;\n"
    << "      } else if (a < -pivot_tol && basis[i] < g) {\n        limit = (2.0 - value[i]) / -a;\n        to_upper = 1;\n"
    << "      } else {\n        continue;\n      }\n"
    << "      if (limit < theta || (limit == theta && leave >= 0 && basis[i] < basis[leave])) {\n"
    << "        theta = 0.0 < limit ? limit : 0.0;\n        leave = i;\n        leave_to_upper = to_upper;\n      }\n    }\n"
    << "    for (i = 0; i < " << p << "ROWS; ++i)\n      value[i] -= theta * dir * tableau[i][enter];\n"
    << "    if (leave < 0) {\n      at_upper[enter] = (unsigned char)!at_upper[enter];\n      continue;\n    }\n"
    << "    out = basis[leave];\n    is_basic[out] = 0;\n"
    << "    if (out < g)\n      at_upper[out] = leave_to_upper;\n"
    << "    entering_value = at_upper[enter] ? 2.0 - theta : theta;\n"
    << "    at_upper[enter] = 0;\n    is_basic[enter] = 1;\n    basis[leave] = enter;\n    value[leave] = entering_value;\n"
    << "    piv = tableau[leave][enter];\n"
    << "    for (j = 0; j < cols; ++j)\n      tableau[leave][j] /= piv;\n"
    << "    for (i = 0; i < " << p << "ROWS; ++i) {\n      double f;\n"
    << "      if (i == leave)\n        continue;\n"
    << "      f = tableau[i][enter];\n      if (f == 0.0)\n        continue;\n"
    << "      for (j = 0; j < cols; ++j)\n        tableau[i][j] -= f * tableau[leave][j];\n    }\n  }\n"
    << "  for (j = 0; j < g; ++j)\n    if (!is_basic[j])\n      xi[j] = at_upper[j] ? 1.0 : -1.0;\n"
    << "  for (i = 0; i < " << p << "ROWS; ++i)\n    if (basis[i] < g) {\n"
    << "      const double v = value[i] - 1.0;\n"
    << "      xi[basis[i]] = v < -1.0 ? -1.0 : (1.0 < v ? 1.0 : v);\n    }\n}\n\n";
}

std::string header(const FunnelData& d, const std::string& prefix, const ExportRequest& req) {
  c_source::CHeader h;
  h.prefix = prefix;
  h.n = d.n;
  h.m = d.m;
  h.horizon = d.horizon();
  h.tau = d.tau;
  h.invariant_from = d.invariant_from;
  h.about = prefix + ".h: funnel controller of agent '" + d.agent + "' (" + d.dynamics_type + "), generated by `marsyn export`" +
            (req.source.empty() ? "" : " from " + req.source) +
            ".\n * Dependency-free C99 (docs/deploy.md): u = sat_U(u_k + K_k (x - x_k)) for x in the verified set V_k,\n"
            " * bit for bit as marsyn's FunnelController::input; " +
            prefix + "_inside(x, k) is V_k's membership test.\n * No allocation, no state.";
  return c_source::header_text(h);
}

// The controller's data: nominal, gains, eps, U, and the verified sets' kinds, offsets and numbers.
void write_tables(std::ostringstream& c, const FunnelData& d, const SetPool& pool, const std::string& p) {
  const int n = d.n, m = d.m, T = d.horizon();
  auto vec_table = [&](const std::string& what, const std::string& name, const std::vector<std::vector<double>>& rows,
                       int steps, int cols) {
    c << "/* " << what << " */\nstatic const double " << p << name << "[" << steps << "][" << cols << "] = ";
    array_body_2d(c, steps, cols, [&](long long i) { return hex_double(rows[static_cast<size_t>(i / cols)][static_cast<size_t>(i % cols)]); });
    c << ";\n";
  };
  vec_table("nominal states x_k (k = 0..T)", "xk", d.x_nom, T + 1, n);
  vec_table("nominal inputs u_k", "uk", d.u_nom, T, m);
  vec_table("gains K_k, m x n row-major", "K", d.K, T, m * n);
  c << "static const double " << p << "eps[" << n << "] = ";
  array_body(c, n, [&](long long i) { return hex_double(d.eps[static_cast<size_t>(i)]); });
  c << ";\nstatic const double " << p << "ulo[" << m << "] = ";
  array_body(c, m, [&](long long i) { return hex_double(d.u_lo[static_cast<size_t>(i)]); });
  c << ";\nstatic const double " << p << "uhi[" << m << "] = ";
  array_body(c, m, [&](long long i) { return hex_double(d.u_hi[static_cast<size_t>(i)]); });
  c << ";\n\n/* V_k within box_k: 0 nothing more (the initial box), 1 parallelotope |S (x - c)|_inf <= 1, 2 zonotope\n"
       " * c + G xi, 3 zonotope c + [G' | diag(r)] xi; + 4: box_k is stored (else it is x_k +- eps rounded inward) */\n"
    << "static const uint8_t " << p << "kind[" << T + 1 << "] = ";
  array_body(c, T + 1, [&](long long k) { return std::to_string(pool.kind[static_cast<size_t>(k)]); });
  if (pool.any_zonotope) {
    c << ";\n/* generators of zonotope steps */\nstatic const uint8_t " << p << "gens[" << T + 1 << "] = ";
    array_body(c, T + 1, [&](long long k) { return std::to_string(d.sets[static_cast<size_t>(k)].generators); });
  }
  c << ";\n/* where step k's numbers start in set[]: [box lo, hi (n each)], then c (n) and S (n x n row-major),\n"
       " * or c, G (n x g column-major) and tol (n), or c, G' (n x (g - n)), r (n) and tol */\n"
    << "static const uint" << 8 * pool.offset_bytes << "_t " << p << "at[" << T + 1 << "] = ";
  array_body(c, T + 1, [&](long long k) { return std::to_string(pool.at[static_cast<size_t>(k)]); });
  c << ";\nstatic const double " << p << "set[" << std::max<size_t>(1, pool.values.size()) << "] = ";
  array_body(c, static_cast<long long>(pool.values.size()), [&](long long i) { return hex_double(pool.values[static_cast<size_t>(i)]); });
  c << ";\n\n";
  if (pool.any_zonotope) {
    c << "/* zonotope steps: the least-norm map P = G' (G G')^-1 (g x n row-major) at fast[fast_at[k]], -1: none;\n"
         " * its coefficients are tried before the simplex's, and the same residual test decides */\n"
      << "static const int32_t " << p << "fast_at[" << T + 1 << "] = ";
    array_body(c, T + 1, [&](long long k) { return std::to_string(pool.fast_at[static_cast<size_t>(k)]); });
    c << ";\nstatic const double " << p << "fast[" << std::max<size_t>(1, pool.fast.size()) << "] = ";
    array_body(c, static_cast<long long>(pool.fast.size()), [&](long long i) { return hex_double(pool.fast[static_cast<size_t>(i)]); });
    c << ";\n\n";
  }
}

// a - b rounded up and a + b rounded down, for the steps whose box is x_k +- eps.
void write_rounding_helpers(std::ostringstream& c, const std::string& p) {
  c << "/* a - b rounded up and a + b rounded down with round-to-nearest operations only: TwoSum's exact error\n"
       " * says which way the sum was rounded, t +- 2^-53 (1 + 2^-52) |t| is the neighbouring double. marsyn\n"
       " * checked at export that this gives box_k's stored bits at every step it is used for. */\n"
    << "static double " << p << "up_difference(double a, double b)\n{\n"
    << "  const double t = a - b, bb = t - a, e = (a - (t - bb)) + (-b - bb);\n"
    << "  return e > 0.0 ? t + 0x1.0000000000001p-53 * fabs(t) : t;\n}\n\n"
    << "static double " << p << "down_sum(double a, double b)\n{\n"
    << "  const double t = a + b, bb = t - a, e = (a - (t - bb)) + (b - bb);\n"
    << "  return e < 0.0 ? t - 0x1.0000000000001p-53 * fabs(t) : t;\n}\n\n";
}

bool any_periodic(const FunnelData& d) { return std::find(d.periodic.begin(), d.periodic.end(), 1) != d.periodic.end(); }

// A controller with periodic coordinates reads an angle on any branch: lifted onto the nominal
// x_k's, with the same two operations and remainder as marsyn::lift_angle (FunnelController).
void write_lift(std::ostringstream& c, const FunnelData& d, const std::string& p) {
  if (!any_periodic(d)) return;
  c_source::lift_function(c, p);
  c << "/* x_read with its periodic coordinates (";
  for (int i = 0; i < d.n; ++i)
    if (d.periodic[static_cast<size_t>(i)]) c << " " << i;
  c << " ) on the nominal's branch, in x */\nstatic const double *" << p << "lifted(const double *x_read, int k, double *x)\n{\n"
    << "  int j;\n  for (j = 0; j < " << d.n << "; ++j)\n    x[j] = x_read[j];\n";
  for (int i = 0; i < d.n; ++i)
    if (d.periodic[static_cast<size_t>(i)]) c << "  x[" << i << "] = " << p << "lift(x_read[" << i << "], " << p << "xk[k][" << i << "]);\n";
  c << "  return x;\n}\n\n";
}

std::string lifted_declaration(const FunnelData& d) {
  return any_periodic(d) ? "  double x_lifted[" + std::to_string(d.n) + "];\n  const double *x = x_read;\n" : "  const double *x = x_read;\n";
}

std::string lifted_call(const FunnelData& d, const std::string& p) {
  return any_periodic(d) ? "  x = " + p + "lifted(x_read, k, x_lifted);\n" : "";
}

// PREFIX_inside(x, k): V_k's membership test.
void write_inside(std::ostringstream& c, const FunnelData& d, const SetPool& pool, const std::string& prefix,
                  bool any_eps_box) {
  const std::string p = prefix + "_";
  const int n = d.n, T = d.horizon();
  c << "int " << prefix << "_inside(const double *x_read, int k)\n{\n  const double *c;\n  int i, j, kind;\n"
    << lifted_declaration(d)
    << "  if (k < 0 || k > " << T << ")\n    return 0;\n"
    << lifted_call(d, p)
    << "  c = " << p << "set + " << p << "at[k];\n  kind = " << p << "kind[k];\n"
    << "  if (kind & 4) {\n"
    << "    for (j = 0; j < " << n << "; ++j)\n"
    << "      if (!(x[j] >= c[j] && x[j] <= c[" << n << " + j]))\n        return 0; /* also NaN */\n"
    << "    c += " << 2 * n << ";\n    kind &= 3;\n  }";
  if (any_eps_box)
    c << " else {\n    for (j = 0; j < " << n << "; ++j)\n"
      << "      if (!(x[j] >= " << p << "up_difference(" << p << "xk[k][j], " << p << "eps[j]) && x[j] <= " << p << "down_sum("
      << p << "xk[k][j], " << p << "eps[j])))\n        return 0;\n  }";
  c << "\n";
  if (pool.any_zonotope) {
    const int G = std::max(1, pool.max_generators);
    c << "  if (kind >= 2) {\n"
      << "    const int g = " << p << "gens[k], dense = kind == 3 ? g - " << n << " : g;\n"
      << "    const double *tol = c + " << n << " + " << n << " * dense + (kind == 3 ? " << n << " : 0);\n"
      << "    double G[" << n * G << "], d[" << n << "], xi[" << G << "];\n"
      << "    for (j = 0; j < " << n << " * dense; ++j)\n      G[j] = c[" << n << " + j];\n"
      << "    for (j = dense; j < g; ++j) /* the axis generators: +0.0 off the diagonal, as in the .ctrl file */\n"
      << "      for (i = 0; i < " << n << "; ++i)\n        G[j * " << n << " + i] = i == j - dense ? c[" << n << " + " << n
      << " * dense + i] : 0.0;\n"
      << "    for (j = 0; j < " << n << "; ++j)\n      d[j] = x[j] - c[j];\n"
      << "    if (" << p << "fast_at[k] >= 0) {\n"
      << "      const double *P = " << p << "fast + " << p << "fast_at[k];\n      int ok = 1;\n"
      << "      for (j = 0; j < g; ++j) {\n        double s = 0.0;\n"
      << "        for (i = 0; i < " << n << "; ++i)\n          s += P[j * " << n << " + i] * d[i];\n        xi[j] = s;\n      }\n"
      << "      for (j = 0; j < g && ok; ++j)\n        if (!(fabs(xi[j]) <= 1.0))\n          ok = 0;\n"
      << "      for (i = 0; i < " << n << " && ok; ++i) {\n        double r = -d[i];\n"
      << "        for (j = 0; j < g; ++j)\n          r += G[j * " << n << " + i] * xi[j];\n"
      << "        if (!(fabs(r) <= tol[i]))\n          ok = 0;\n      }\n"
      << "      if (ok)\n        return 1;\n    }\n"
      << "    " << p << "coefficients(G, g, d, xi);\n"
      << "    /* the residual allowance holds for coefficients in the cube only */\n"
      << "    for (j = 0; j < g; ++j)\n      if (!(fabs(xi[j]) <= 1.0))\n        return 0;\n"
      << "    for (i = 0; i < " << n << "; ++i) {\n      double r = -d[i];\n"
      << "      for (j = 0; j < g; ++j)\n        r += G[j * " << n << " + i] * xi[j];\n"
      << "      if (!(fabs(r) <= tol[i]))\n        return 0;\n    }\n    return 1;\n  }\n";
  }
  if (pool.any_parallelotope) {
    c << "  if (kind == 1) {\n"
      << "    /* the rounding of exactly this loop is bounded by the verification (docs/soundness.md section 11) */\n"
      << "    const double *S = c + " << n << ";\n"
      << "    for (i = 0; i < " << n << "; ++i) {\n      double y = 0.0;\n"
      << "      for (j = 0; j < " << n << "; ++j)\n        y += S[i * " << n << " + j] * (x[j] - c[j]);\n"
      << "      if (!(fabs(y) <= 1.0))\n        return 0;\n    }\n  }\n";
  }
  if (!pool.any_zonotope && !pool.any_parallelotope) c << "  (void)i;\n  (void)kind;\n";
  c << "  return 1;\n}\n\n";
}

// PREFIX_input(x, k, u): the saturated law inside V_k.
void write_input(std::ostringstream& c, const FunnelData& d, const std::string& prefix) {
  const std::string p = prefix + "_", P = c_source::upper(prefix);
  const int n = d.n, m = d.m, T = d.horizon();
  c << "int " << prefix << "_input(const double *x_read, int k, double *u)\n{\n  int i, j;\n"
    << lifted_declaration(d)
    << "  if (k < 0 || k >= " << T << ")\n    return " << P << "_OUTSIDE_HORIZON;\n"
    << lifted_call(d, p)
    << "  if (!" << prefix << "_inside(x, k))\n    return " << P << "_OUTSIDE_DOMAIN;\n"
    << "  for (i = 0; i < " << m << "; ++i) {\n    double acc = " << p << "uk[k][i];\n"
    << "    for (j = 0; j < " << n << "; ++j)\n      acc += " << p << "K[k][i * " << n << " + j] * (x[j] - " << p << "xk[k][j]);\n"
    << "    u[i] = acc < " << p << "ulo[i] ? " << p << "ulo[i] : (" << p << "uhi[i] < acc ? " << p << "uhi[i] : acc);\n  }\n"
    << "  return " << P << "_OK;\n}\n";
}

std::string source(const FunnelData& d, const SetPool& pool, const std::string& prefix, const ExportRequest& req) {
  const std::string p = prefix + "_";
  const int n = d.n, T = d.horizon();
  int counts[3] = {0, 0, 0};
  for (const StepSet& s : d.sets) ++counts[s.kind];
  std::ostringstream c;
  c << "/* " << prefix << ".c: funnel controller of agent '" << d.agent << "', generated by `marsyn export`"
    << (req.source.empty() ? "" : " from " + req.source) << ".\n * " << T << " steps; verified sets: " << counts[kBox]
    << " boxes, " << counts[kParallelotope] << " parallelotopes, " << counts[kZonotope] << " zonotopes; const data "
    << const_bytes(d, pool) << " bytes. */\n"
    << c_source::source_preamble(prefix, true);
  write_tables(c, d, pool, p);
  const bool any_eps_box = std::any_of(pool.kind.begin(), pool.kind.end(), [](int k) { return !(k & kExplicitBox); });
  if (any_eps_box) write_rounding_helpers(c, p);
  if (pool.any_zonotope) write_solver(c, p, n, pool.max_generators);
  write_lift(c, d, p);
  write_inside(c, d, pool, prefix, any_eps_box);
  write_input(c, d, prefix);
  return c.str();
}

}  // namespace

long long c_const_bytes(const FunnelData& d) { return const_bytes(d, pool_of(d)); }

ExportResult export_c(const FunnelData& d, const ExportRequest& req) {
  ExportResult r;
  std::string prefix;
  if (!c_source::c_request_prefix(req, d.agent, prefix, r)) return r;
  const SetPool pool = pool_of(d);
  if (pool.fast.size() > 0x7FFFFFFFull) {
    r.message = "the least-norm maps hold more than 2^31 numbers; the C tables index them with 32 bits";
    return r;
  }
  if (pool.values.size() > 0xFFFFFFFFull) {
    r.message = "the verified sets hold more than 2^32 numbers; the C tables index them with 32 bits";
    return r;
  }
  if (!c_source::write_header_and_source(req, prefix, header(d, prefix, req), source(d, pool, prefix, req), r)) return r;
  r.ok = true;
  r.encoding = "plain";
  r.const_data_bytes = const_bytes(d, pool);
  r.entries = d.horizon();
  std::ostringstream msg;
  msg << "agent " << d.agent << ": funnel controller, " << d.horizon() << " steps, const data " << r.const_data_bytes << " bytes";
  r.message = msg.str();
  return r;
}

ExportResult FunnelController::export_to(const ExportRequest& request) const {
  if (request.format == "c") return export_c(data_, request);
  ExportResult r;
  if (request.format == "scs")
    r.message = "SCOTS' format lists a grid controller's (cell, input) pairs and a funnel controller has no grid "
                "(u = sat(u_k + K_k (x - x_k)) on zonotopes); export it with --format c";
  else
    r.message = "unknown export format '" + request.format + "'; expected c (scs is for abcd controllers only)";
  return r;
}

}  // namespace marsyn::funnel
