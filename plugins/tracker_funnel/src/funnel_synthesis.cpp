#include "funnel_synthesis.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <optional>

#include <Eigen/LU>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "allowances.hpp"
#include "invariant_sets.hpp"
#include "marsyn/interval.hpp"
#include "marsyn/number_text.hpp"
#include "marsyn/period_part.hpp"
#include "membership.hpp"
#include "period_law.hpp"

namespace marsyn::funnel {
namespace {

using fast_detail::add_up;
using fast_detail::mul_up;

FastInterval fi(double v) { return FastInterval(v); }

// The stored box of step k: inside [x_k - eps, x_k + eps] in exact arithmetic.
void eps_box(const Eigen::VectorXd& xk, const Eigen::VectorXd& eps, std::vector<double>& lo, std::vector<double>& hi) {
  const int n = static_cast<int>(xk.size());
  lo.resize(n);
  hi.resize(n);
  for (int i = 0; i < n; ++i) {
    lo[i] = (fi(xk[i]) - fi(eps[i])).upper();
    hi[i] = (fi(xk[i]) + fi(eps[i])).lower();
  }
}


struct Fit {
  bool ok = false;
  std::uint8_t kind = kParallelotope;
  std::vector<double> S;  // parallelotope: n x n row-major; zonotope: G column-major
  int generators = 0;
  std::vector<double> tol;
  double volume = 0.0;    // parallelotope: |det S^-1|, up to the common factor 2^n
};

// V = {x in box : the solver's xi leaves |fl(G xi - (x - c))| <= tol} for the reduction c + G xi
// of z to `order` generators per state. z lies in the reduction; that the solver accepts every
// state of z (completeness) is what the soundness tests sample (docs/soundness.md section 11).
Fit certify_zonotope(const Zonotope& zend, int order) {
  Fit f;
  f.kind = kZonotope;
  const int n = zend.dim();
  Zonotope z = zend;
  reduce_order(z, 0, std::min(order * n, kMaxMembershipGenerators));
  // A relative margin of 1e-6 about the centre: reachable states at a vertex of an (unreduced,
  // hence tight) enclosure would otherwise sit on the boundary, where the solver's tolerances
  // can refuse them (measured: 144 in 1e6 vertex samples of the unicycle at order 8). The proof
  // only needs the next period to start from what is stored, and it does (f.next below).
  z.G *= 1.0 + 1e-6;
  const int p = z.generators();
  if (p > kMaxMembershipGenerators || p < 1) return f;
  f.tol.resize(n);
  for (int i = 0; i < n; ++i) {
    f.tol[i] = std::max(1e-9 * z.radius(i), 1e-300);
    if (!std::isfinite(f.tol[i])) return f;
  }
  f.generators = p;
  f.S.assign(z.G.data(), z.G.data() + static_cast<std::size_t>(n) * p);
  f.ok = true;
  return f;
}

// Candidate shapes S (rows scaled so that |S (x - c)|_inf <= 1 roughly bounds z): the principal
// axes of the generators, the closed loop's real eigenbasis, the LQR cost-to-go's axes and the
// coordinate axes. Any shape is sound: certify() checks containment in interval arithmetic.
// z: one zonotope containing the parts (their union's generators and centre offsets), for the
// axes; the rows are scaled to the parts themselves.
std::vector<Eigen::MatrixXd> candidate_shapes(const Zonotope& z, const std::vector<Zonotope>& parts,
                                              const Eigen::MatrixXd* closed, const Eigen::MatrixXd* cost,
                                              const Eigen::MatrixXd* basis = nullptr) {
  const int n = z.dim();
  std::vector<Eigen::MatrixXd> candidates, shapes;
  if (z.generators() < n) return shapes;  // degenerate (no disturbance and a flat set)
  if (basis && basis->rows() == n && basis->cols() == n && basis->allFinite()) candidates.push_back(*basis);
  {
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(z.G, Eigen::ComputeFullU);
    const auto& sv = svd.singularValues();
    if (sv[n - 1] > 1e-12 * sv[0]) candidates.push_back(svd.matrixU() * sv.asDiagonal());
  }
  if (closed && closed->rows() == n) {
    Eigen::EigenSolver<Eigen::MatrixXd> es(*closed);
    if (es.info() == Eigen::Success) {
      Eigen::MatrixXd E(n, n);
      const auto values = es.eigenvalues();
      const auto vectors = es.eigenvectors();
      for (int j = 0; j < n; ++j) {
        E.col(j) = vectors.col(j).real();
        if (values[j].imag() != 0.0 && j + 1 < n) {
          E.col(j + 1) = vectors.col(j).imag();
          ++j;
        }
      }
      if (E.allFinite()) candidates.push_back(E);
    }
  }
  if (cost && cost->rows() == n) {
    // The LQR cost-to-go's principal axes: the closed loop contracts in that norm.
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(*cost);
    if (es.info() == Eigen::Success && es.eigenvalues().minCoeff() > 0)
      candidates.push_back(es.eigenvectors() * es.eigenvalues().cwiseSqrt().cwiseInverse().asDiagonal());
  }
  {
    Eigen::VectorXd r(n);
    for (int i = 0; i < n; ++i) r[i] = std::max(z.radius(i), 1e-300);
    candidates.push_back(r.asDiagonal());
  }
  for (const auto& T0 : candidates) {
    Eigen::FullPivLU<Eigen::MatrixXd> lu(T0);
    if (!lu.isInvertible()) continue;
    const Eigen::MatrixXd Tinv = lu.inverse();
    if (!Tinv.allFinite()) continue;
    Eigen::VectorXd scale = Eigen::VectorXd::Zero(n);
    for (const Zonotope& part : parts) {
      const Eigen::MatrixXd Y = Tinv * part.G;
      for (int i = 0; i < n; ++i) {
        double s = Y.row(i).lpNorm<1>();
        if (parts.size() > 1) s += std::fabs(Tinv.row(i).dot(part.c - z.c));
        scale[i] = std::max(scale[i], s);
      }
    }
    Eigen::MatrixXd S = Tinv;
    for (int i = 0; i < n; ++i) S.row(i) /= scale[i] * (1 + 1e-9);
    if (S.allFinite()) shapes.push_back(S);
  }
  return shapes;
}

// V = {x in box : |fl(S (x - c))|_inf <= 1}, with S rescaled until V contains every part
// (checked in interval arithmetic, rounding of the evaluation included): part c_q + G_q xi
// gives S_i (x - c) in S_i (c_q - c) + sum_l |S_i g_l| [-1, 1].
Fit certify(const std::vector<Zonotope>& parts, const Eigen::VectorXd& c, const Eigen::MatrixXd& S0, const std::vector<double>& lo,
            const std::vector<double>& hi) {
  Fit f;
  const int n = static_cast<int>(c.size());
  StepSet t;
  t.lo = lo;
  t.hi = hi;
  t.kind = kParallelotope;
  t.c.assign(c.data(), c.data() + n);
  t.S.resize(static_cast<std::size_t>(n) * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) t.S[static_cast<std::size_t>(i) * n + j] = S0(i, j);
  for (int attempt = 0; attempt < 4; ++attempt) {
    bool inside = true;
    for (int i = 0; i < n; ++i) {
      const double need = parallelotope_row_need(t, i, parts, n);
      if (!std::isfinite(need)) return f;
      if (need > 1.0) {
        inside = false;
        for (int j = 0; j < n; ++j) t.S[static_cast<std::size_t>(i) * n + j] *= (1.0 / need) * (1 - 1e-12);
      }
    }
    if (inside) {
      f.ok = true;
      break;
    }
  }
  if (!f.ok) return f;
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> S(t.S.data(), n, n);
  f.volume = std::fabs(Eigen::MatrixXd(S).partialPivLu().determinant());
  f.volume = f.volume > 0 ? 1.0 / f.volume : std::numeric_limits<double>::infinity();
  f.S = std::move(t.S);
  return f;
}

// One zonotope containing every part: centre c (the midpoint of their hull), the parts'
// generators side by side and each part's offset c_q - c as a generator of its own (a state of
// part q takes its own coefficients, 1 on its offset and 0 elsewhere). The part itself if one.
Zonotope union_zonotope(const std::vector<Zonotope>& parts) {
  if (parts.size() == 1) return parts.front();
  const int n = parts.front().dim();
  Zonotope u;
  u.c.resize(n);
  Eigen::Index p = 0;
  for (const Zonotope& z : parts) p += z.generators() + 1;
  for (int i = 0; i < n; ++i) {
    double a = std::numeric_limits<double>::infinity(), b = -a;
    for (const Zonotope& z : parts) {
      const FastInterval h = z.hull(i);
      a = std::min(a, h.lower());
      b = std::max(b, h.upper());
    }
    u.c[i] = 0.5 * a + 0.5 * b;
  }
  // The offsets c_q - c are rounded: their error goes into a box (from_intervals).
  IVector centre(n);
  IMatrix gens(n, static_cast<int>(p));
  int col = 0;
  for (const Zonotope& z : parts) {
    for (int l = 0; l < z.generators(); ++l, ++col)
      for (int i = 0; i < n; ++i) gens(i, col) = fi(z.G(i, l));
    for (int i = 0; i < n; ++i) gens(i, col) = fi(z.c[i]) - fi(u.c[i]);
    ++col;
  }
  for (int i = 0; i < n; ++i) centre[i] = fi(u.c[i]);
  return from_intervals(centre, gens, {});
}

// The stored V_{k+1}, certified to contain every part of the end enclosure: by default the
// parallelotope of least volume (one O(n^2) test per call), else a zonotope; with
// zonotope_sets, the zonotope of order set_order first (tighter, a simplex per call at worst).
// Any certified candidate is sound. Split parts share one set about their union's centre
// (`centre`), so the controller's test stays one set per step.
Fit verified_set(const std::vector<Zonotope>& parts, Eigen::VectorXd& centre, const std::vector<double>& lo,
                 const std::vector<double>& hi, const Eigen::MatrixXd* closed, const Eigen::MatrixXd* cost,
                 const VerifyOptions& o, const Eigen::MatrixXd* basis = nullptr) {
  const Zonotope zend = union_zonotope(parts);
  centre = zend.c;
  const int n = zend.dim();
  const int order = std::max(o.set_order, 2);
  if (o.zonotope_sets && zend.generators() > 2 * n) {
    Fit high = certify_zonotope(zend, order);
    if (high.ok) return high;
  }
  Fit best;
  for (const Eigen::MatrixXd& S : candidate_shapes(zend, parts, closed, cost, basis)) {
    Fit c = certify(parts, centre, S, lo, hi);
    if (c.ok && (!best.ok || c.volume < best.volume)) best = std::move(c);
  }
  if (best.ok) return best;
  Fit low = certify_zonotope(zend, 2);
  if (low.ok || order == 2) return low;
  return certify_zonotope(zend, order);
}

// The law's data as the controller file stores it: the problem's numbers, the nominal and K.
void describe_law(const TrackingProblem& p, const std::vector<Eigen::MatrixXd>& K, FunnelData& d) {
  const Dynamics& f = *p.dynamics;
  const int n = f.state_dim(), m = f.input_dim();
  const int T = static_cast<int>(p.nominal.u.size());
  d.dynamics_type = f.type();
  d.agent = p.agent;
  if (const auto per = f.periodic(); std::find(per.begin(), per.end(), true) != per.end())
    for (bool q : per) d.periodic.push_back(q ? 1 : 0);
  d.n = n;
  d.m = m;
  d.tau = p.tau;
  d.eps.assign(p.tube.eps.data(), p.tube.eps.data() + n);
  d.w.assign(p.tube.w.data(), p.tube.w.data() + n);
  d.dist = DisturbanceBound(p.tube);
  d.u_lo.assign(p.input_bounds.lo.data(), p.input_bounds.lo.data() + m);
  d.u_hi.assign(p.input_bounds.hi.data(), p.input_bounds.hi.data() + m);
  for (int k = 0; k <= T; ++k) d.x_nom.emplace_back(p.nominal.x[k].data(), p.nominal.x[k].data() + n);
  for (int k = 0; k < T; ++k) {
    d.u_nom.emplace_back(p.nominal.u[k].data(), p.nominal.u[k].data() + m);
    std::vector<double> row(static_cast<std::size_t>(m) * n);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < n; ++j) row[static_cast<std::size_t>(i) * n + j] = K[k](i, j);
    d.K.push_back(std::move(row));
  }
}

// V_0, the initial box x_0 +- radius, stored as it is tested (plain comparisons, no rounding),
// and the zonotope the first period starts from; false (and why) when the box leaves the eps-box.
bool initial_set(const TrackingProblem& p, const Eigen::VectorXd& radius, StepSet& s0, Zonotope& zx, std::string& why) {
  const int n = p.dynamics->state_dim();
  std::vector<double> elo, ehi;
  eps_box(p.nominal.x[0], p.tube.eps, elo, ehi);
  s0.lo.resize(n);
  s0.hi.resize(n);
  for (int i = 0; i < n; ++i) {
    s0.lo[i] = (fi(p.nominal.x[0][i]) - fi(radius[i])).lower();
    s0.hi[i] = (fi(p.nominal.x[0][i]) + fi(radius[i])).upper();
    if (s0.lo[i] < elo[i] || s0.hi[i] > ehi[i]) {
      why = "the initial box (radius " + number_text(radius[i], 4) + " along " + p.dynamics->state_names()[i] +
            ") is not inside the eps-box (eps " + number_text(p.tube.eps[i], 4) + ")";
      return false;
    }
  }
  IVector c(n);
  for (int i = 0; i < n; ++i) c[i] = FastInterval(s0.lo[i], s0.hi[i]);
  std::vector<double> meas(n);
  for (int i = 0; i < n; ++i) meas[i] = measured(s0.lo[i], s0.hi[i]);
  zx = from_intervals(c, IMatrix(n, 0), meas);
  return true;
}

// Whether the end enclosure of step k leaves box_{k+1}; if so, out says where, by how much and
// whether the enclosure is off the nominal rather than wide.
bool leaves_tube(const Zonotope& zend, const StepSet& next, const TrackingProblem& p, int k, VerifyOutcome& out) {
  const int n = zend.dim(), T = static_cast<int>(p.nominal.u.size());
  for (int i = 0; i < n; ++i) {
    const FastInterval h = zend.hull(i);
    if (h.lower() < next.lo[i] || h.upper() > next.hi[i]) {
      const double over = std::max(next.lo[i] - h.lower(), h.upper() - next.hi[i]);
      const double offset = std::fabs(zend.c[i] - p.nominal.x[k + 1][i]);
      out.miss_off_centre = offset > zend.radius(i);
      out.why = "at step " + std::to_string(k + 1) + " of " + std::to_string(T) + ", " + p.dynamics->state_names()[i] +
                " can leave the eps-tube by " + number_text(over, 4) + " (enclosure half-width " + number_text(zend.radius(i), 4) +
                " vs eps " + number_text(p.tube.eps[i], 4) + (out.miss_off_centre ? ", its centre " + number_text(offset, 4) + " off the nominal" : "") +
                (out.saturated_steps ? "; some inputs saturated" : "") + ")";
      out.reached_step = k;
      out.miss_coordinate = i;
      out.miss_amount = over;
      return true;
    }
  }
  return false;
}

// The generator to split along: the widest relative to eps (max_i |g_i| / eps_i), whose halving
// shrinks the parts most where the tube is narrow.
int widest_generator(const Zonotope& z, const Eigen::VectorXd& eps) {
  int best = 0;
  double width = -1.0;
  for (int l = 0; l < z.generators(); ++l) {
    double w = 0.0;
    for (int i = 0; i < z.dim(); ++i) w = std::max(w, std::fabs(z.G(i, l)) / eps[i]);
    if (w > width) {
      width = w;
      best = l;
    }
  }
  return best;
}

// Reducing a part to few generators before splitting it (so that one split halves more of it)
// verified less far: on the 12-state quadrotor at 4x the test disturbance, reduced to n, 2 n or
// 6 n generators first, 17, 20 and 23 steps of 30, against 25 split as carried.
std::pair<Zonotope, Zonotope> split_widest(const Zonotope& z, const Eigen::VectorXd& eps) {
  return split(z, widest_generator(z, eps));
}

// The inputs enclosed as saturated boxes up to the miss, each with the steps it was (how many,
// the first and the last) and how far the law's hull reached past U (the largest excess and its
// step): ": v on 12 steps (40-52), its hull up to 0.35 past U (step 47)". Empty if none was.
std::string saturation_report(const VerifyOutcome& out, const TrackingProblem& p) {
  const int m = p.dynamics->input_dim();
  const std::vector<std::string> names = p.dynamics->input_names();
  std::string note;
  for (int i = 0; i < m; ++i) {
    int count = 0, first = -1, last = -1, worst_step = -1;
    double worst = 0.0;
    for (std::size_t k = 0; k < out.input_boxed.size(); ++k) {
      if (!out.input_boxed[k][i]) continue;
      ++count;
      if (first < 0) first = static_cast<int>(k);
      last = static_cast<int>(k);
      const FastInterval& h = out.input_hull[k][i];
      const double over = std::max(h.upper() - p.input_bounds.hi[i], p.input_bounds.lo[i] - h.lower());
      if (over > worst) {
        worst = over;
        worst_step = static_cast<int>(k);
      }
    }
    if (!count) continue;
    note += note.empty() ? ": " : "; ";
    note += names[i] + " on " + std::to_string(count) + " step(s) (" + std::to_string(first) +
            (last > first ? "-" + std::to_string(last) : std::string()) + "), its hull up to " + number_text(worst, 4) +
            " past U (step " + std::to_string(worst_step) + ")";
  }
  return note;
}

}  // namespace

bool fit_parallelotope(const std::vector<Zonotope>& parts, StepSet& set, const Eigen::MatrixXd* closed, const Eigen::MatrixXd* basis,
                       const VerifyOptions& o) {
  VerifyOptions po = o;
  po.zonotope_sets = false;
  Eigen::VectorXd centre;
  Fit fit = verified_set(parts, centre, set.lo, set.hi, closed, nullptr, po, basis);
  if (!fit.ok || fit.kind != kParallelotope) return false;
  set.kind = kParallelotope;
  set.c.assign(centre.data(), centre.data() + centre.size());
  set.S = std::move(fit.S);
  set.generators = 0;
  set.tol.clear();
  return true;
}

bool fit_zonotope(const Zonotope& z, int order, StepSet& set) {
  if (z.dim() > kMaxMembershipRows) return false;
  Fit fit = certify_zonotope(z, order);
  if (!fit.ok) return false;
  set.kind = kZonotope;
  set.c.assign(z.c.data(), z.c.data() + z.dim());  // a reduction keeps the centre
  set.S = std::move(fit.S);
  set.generators = fit.generators;
  set.tol = std::move(fit.tol);
  return true;
}

FlowOptions flow_options(const TrackingProblem& p, const VerifyOptions& o) {
  FlowOptions flow = o.flow;
  flow.tau = p.tau;
  const int n = p.dynamics->state_dim(), N = n + p.dynamics->input_dim();
  // The reachable set is carried with reach_order generators per state (the period adds n + m
  // and reduces back): a reduction boxes generators, and boxing at every step makes a contracting
  // closed loop's enclosure grow linearly (measured on the crane: to eps in 55 steps, against 0.3
  // eps for the linearized closed loop; with 24 n generators it stays within 0.3-0.5 eps).
  if (flow.max_generators <= 0) flow.max_generators = std::max(3 * N, std::max(o.reach_order, 1) * n + N);
  return flow;
}

double rounding_factor(int terms) {
  // gamma_{terms + 2} = (terms + 2) u / (1 - (terms + 2) u), u = 2^-53, rounded up generously.
  return (terms + 3) * 0x1p-52;
}

// Between the samples of step k: the a priori boxes of the period, hulled part by part (and over
// the periods of a split set's parts), with their workspace footprint.
void append_period_enclosures(const std::vector<const FlowResult*>& frs, const TrackingProblem& p, int k, int parts, int spp,
                              std::vector<PeriodEnclosure>& out) {
  const int n = p.dynamics->state_dim(), wd = p.workspace.dim();
  for (int part = 0; part < parts; ++part) {
    PeriodEnclosure e = period_part(k, part, parts, p.tau, n, wd);
    std::vector<Interval> xi(n);
    for (int i = 0; i < n; ++i) {
      FastInterval b = frs.front()->boxes[static_cast<std::size_t>(part * spp) * n + i];
      for (const FlowResult* fr : frs)
        for (int s = part * spp; s < (part + 1) * spp; ++s) b = marsyn::hull(b, fr->boxes[static_cast<std::size_t>(s) * n + i]);
      e.state.lo[i] = b.lower();
      e.state.hi[i] = b.upper();
      xi[i] = Interval(b.lower(), b.upper());
    }
    Interval pw[kMaxWorkspaceDim];
    workspace_point(*p.dynamics, p.workspace, xi.data(), pw);
    for (int c = 0; c < wd; ++c) {
      e.workspace.lo[c] = pw[c].lower();
      e.workspace.hi[c] = pw[c].upper();
    }
    out.push_back(std::move(e));
  }
}

namespace {

// verify_funnel's run over the horizon: the carried set as parts whose union contains every
// reachable state (one part unless a period missed the tube and was split, split_depth times at
// most along any line of splits), the starts kept for a rewind, and the fill figures.
class FunnelVerifier {
 public:
  FunnelVerifier(const TrackingProblem& p, const std::vector<Eigen::MatrixXd>& K,
                 const std::vector<Eigen::MatrixXd>& closed, const VerifyOptions& o,
                 const std::vector<Eigen::MatrixXd>& cost)
      : p_(p), K_(K), closed_(closed), cost_(cost), o_(o), n_(p.dynamics->state_dim()), m_(p.dynamics->input_dim()),
        T_(static_cast<int>(p.nominal.u.size())) {}

  VerifyOutcome run() {
    FunnelData& d = out_.data;
    describe_law(p_, K_, d);
    d.sets.resize(static_cast<std::size_t>(T_) + 1);
    Zonotope zx;
    if (!initial_set(p_, o_.initial_radius, d.sets[0], zx, out_.why)) return std::move(out_);
    if (o_.keep_reach) out_.reach.push_back({zx});
    if (!choose_flow()) return std::move(out_);
    record_fill({zx}, d.sets[0], 0);
    law_.emplace(p_, K_, d, flow_, o_.shift_inputs);
    parts_.push_back({std::move(zx), 0});
    for (int k = 0; k < T_; ++k) {
      if (o_.stop && o_.stop()) {  // the ladder ends on it: no reach or reason of its own to report
        out_.stopped = true;
        return std::move(out_);
      }
      const Step s = step(k);
      if (s == Step::failed) return std::move(out_);
      if (s == Step::last) break;
    }
    out_.mean_fill = fill_count_ ? fill_sum_ / fill_count_ : 0.0;
    out_.reached_step = T_;
    out_.ok = true;
    d.invariant_from = T_ + 1;  // until make_invariant says otherwise
    return std::move(out_);
  }

 private:
  struct Part {
    Zonotope z;
    int depth = 0;
  };
  // A step's start as it was, to split there when splitting at the miss is not enough (the
  // remainders of the periods before it are in the carried set already).
  struct Start {
    int k;
    std::vector<Part> parts;
    double fill_sum, max_fill;
    int fill_count, saturated_steps, shifted_steps;
    long rows, second_order_rows;
  };
  // What a step ends in: the next step, the loop again from an earlier start (rewound), the
  // outcome's failure, or the horizon's end without a fitted V_T.
  enum class Step { next, rewound, failed, last };

  bool choose_flow() {
    flow_ = flow_options(p_, o_);
    if (o_.parts < 1 || flow_.substeps % o_.parts != 0) {
      out_.why = "enclosure_substeps must divide substeps";
      return false;
    }
    spp_ = flow_.substeps / o_.parts;
    return true;
  }

  // How much of the eps-box a verified set spans: its parts' hull, which its box also bounds.
  void record_half_width(const std::vector<Zonotope>& zs, const StepSet& set, int k) {
    std::vector<double> hw(n_, 0.0);
    for (const Zonotope& z : zs)
      for (int i = 0; i < n_; ++i) {
        const FastInterval h = z.hull(i);
        const double xk = p_.nominal.x[k][i];
        hw[i] = std::max(hw[i], std::max(std::min(h.upper(), set.hi[i]) - xk, xk - std::max(h.lower(), set.lo[i])));
      }
    out_.half_width.push_back(std::move(hw));
  }

  void record_fill(const std::vector<Zonotope>& zs, const StepSet& set, int k) {
    record_half_width(zs, set, k);
    for (int i = 0; i < n_; ++i) {
      double radius = zs.front().radius(i);
      if (zs.size() > 1) {  // half the width of the parts' hull
        double a = std::numeric_limits<double>::infinity(), b = -a;
        for (const Zonotope& z : zs) {
          a = std::min(a, z.hull(i).lower());
          b = std::max(b, z.hull(i).upper());
        }
        radius = 0.5 * fast_detail::sub_up(b, a);
      }
      const double r = std::min(radius, 0.5 * (set.hi[i] - set.lo[i])) / p_.tube.eps[i];
      out_.max_fill = std::max(out_.max_fill, r);
      fill_sum_ += r;
      ++fill_count_;
    }
  }

  // The inputs' hull and which rows were boxed, over the step's periods.
  void record_inputs(const std::vector<Period>& periods) {
    std::vector<FastInterval> hull = periods.front().nominal_hull;
    std::vector<char> boxed(m_, 0);
    for (const Period& q : periods)
      for (int i = 0; i < m_; ++i) {
        hull[i] = marsyn::hull(hull[i], q.nominal_hull[i]);
        boxed[i] |= q.boxed[i];
      }
    out_.input_hull.push_back(std::move(hull));
    out_.input_boxed.push_back(std::move(boxed));
  }

  Step step(int& k) {
    FunnelData& d = out_.data;
    if (o_.split_depth > 0 && o_.split_lookback > 0) {
      history_.push_back({k, parts_, fill_sum_, out_.max_fill, fill_count_, out_.saturated_steps, out_.shifted_steps,
                          out_.rows, out_.second_order_rows});
      if (static_cast<int>(history_.size()) > o_.split_lookback + 1) history_.pop_front();
    }
    std::vector<const Zonotope*> starts;
    for (const Part& q : parts_) starts.push_back(&q.z);
    std::vector<Period> periods = law_->best(starts, k);
    out_.periods += static_cast<long>(starts.size());
    record_inputs(periods);
    const std::vector<double> u = periods.front().u;  // one law for every part
    d.u_nom[k] = u;  // the law's u_k (moved inside U where that was verified)
    if (periods.front().shifted) ++out_.shifted_steps;
    StepSet& next = d.sets[k + 1];
    eps_box(p_.nominal.x[k + 1], p_.tube.eps, next.lo, next.hi);
    std::vector<Part> ends;
    std::vector<Period> kept;
    bool saturated = false;
    const Step s = verify_parts(k, u, next, periods, ends, kept, saturated);
    if (s != Step::next) return s;
    if (saturated) ++out_.saturated_steps;
    return store(k, next, ends, kept);
  }

  // The parts' periods of step k under the law u: a part whose period misses is split along its
  // widest generator and verified again under the same law, until it fits or reaches split_depth;
  // then the step rewinds to the earliest start kept, or fails. The parts' ends go to `ends`.
  Step verify_parts(int& k, const std::vector<double>& u, const StepSet& next, std::vector<Period>& periods,
                    std::vector<Part>& ends, std::vector<Period>& kept, bool& saturated) {
    std::vector<Part> todo;
    std::vector<Period> todo_periods;
    for (std::size_t q = parts_.size(); q-- > 0;) {
      todo.push_back(std::move(parts_[q]));
      todo_periods.push_back(std::move(periods[q]));
    }
    while (!todo.empty()) {
      Part q = std::move(todo.back());
      Period cur = std::move(todo_periods.back());
      todo.pop_back();
      todo_periods.pop_back();
      Zonotope zend;
      VerifyOutcome miss;
      miss.saturated_steps = out_.saturated_steps + (saturated || cur.saturated);
      bool fails = !cur.fr.ok;
      if (!fails) {
        zend.c = cur.fr.end.c.head(n_);
        zend.G = cur.fr.end.G.topRows(n_);
        drop_zero_generators(zend);
        // The states at the next sample must lie in the eps-box of x_{k+1}.
        fails = leaves_tube(zend, next, p_, k, miss);
      }
      const bool may_split = out_.periods < static_cast<long>(o_.split_work) * T_;
      if (fails && may_split && q.depth < o_.split_depth && q.z.generators() > 0) {
        auto [lo_half, hi_half] = split_widest(q.z, p_.tube.eps);
        ++out_.splits;
        for (Zonotope* h : {&hi_half, &lo_half}) {
          todo_periods.push_back(law_->with_input(*h, k, u));
          ++out_.periods;
          todo.push_back({std::move(*h), q.depth + 1});
        }
        continue;
      }
      if (fails && may_split && rewinds_ < o_.split_depth && history_.size() > 1 && rewind(k)) return Step::rewound;
      out_.rows += cur.fr.rows;
      out_.second_order_rows += cur.fr.second_order_rows;
      saturated |= cur.saturated;
      for (int i = 0; i < m_; ++i) out_.input_boxed.back()[i] |= cur.boxed[i];
      if (fails) {
        fail(k, cur, miss, saturated);
        return Step::failed;
      }
      ends.push_back({std::move(zend), q.depth});
      kept.push_back(std::move(cur));
    }
    return Step::next;
  }

  // Splits every part that may be split at the earliest start kept, and makes the loop verify
  // from there (k is set so that the loop's ++k reaches it); false when no part could be split.
  bool rewind(int& k) {
    Start back = std::move(history_.front());
    history_.clear();
    std::vector<Part> halves;
    for (Part& b : back.parts) {
      if (b.depth >= o_.split_depth || b.z.generators() == 0) {
        halves.push_back(std::move(b));
        continue;
      }
      auto [lo_half, hi_half] = split_widest(b.z, p_.tube.eps);
      ++out_.splits;
      halves.push_back({std::move(lo_half), b.depth + 1});
      halves.push_back({std::move(hi_half), b.depth + 1});
    }
    if (halves.size() <= back.parts.size()) return false;
    ++rewinds_;
    parts_ = std::move(halves);
    fill_sum_ = back.fill_sum;
    out_.max_fill = back.max_fill;
    fill_count_ = back.fill_count;
    out_.saturated_steps = back.saturated_steps;
    out_.shifted_steps = back.shifted_steps;
    out_.rows = back.rows;
    out_.second_order_rows = back.second_order_rows;
    out_.input_hull.resize(static_cast<std::size_t>(back.k));
    out_.input_boxed.resize(static_cast<std::size_t>(back.k));
    out_.data.enclosures.resize(static_cast<std::size_t>(back.k) * o_.parts);
    out_.half_width.resize(static_cast<std::size_t>(back.k) + 1);
    if (o_.keep_reach) out_.reach.resize(static_cast<std::size_t>(back.k) + 1);
    k = back.k - 1;  // the loop's ++k
    return true;
  }

  // The outcome of a period that missed at step k: no enclosure, or the tube's miss, with which
  // input saturated, where and by how much inside the parenthesis that ends why.
  void fail(int k, const Period& cur, VerifyOutcome& miss, bool saturated) {
    if (saturated) ++out_.saturated_steps;
    if (!cur.fr.ok) {
      out_.why = "no enclosure of the flow over step " + std::to_string(k) + " (the a priori enclosure failed" +
                 (out_.saturated_steps ? "; some inputs saturated" : "") + ")";
      out_.reached_step = k;
    } else {
      out_.why = std::move(miss.why);
      out_.reached_step = miss.reached_step;
      out_.miss_coordinate = miss.miss_coordinate;
      out_.miss_amount = miss.miss_amount;
      out_.miss_off_centre = miss.miss_off_centre;
    }
    if (out_.saturated_steps) out_.why.insert(out_.why.size() - 1, saturation_report(out_, p_));
  }

  // Step k verified: its period enclosures, and V_{k+1} fitted around the parts' ends (it only
  // has to contain them; the next period starts from the parts).
  Step store(int k, StepSet& next, std::vector<Part>& ends, const std::vector<Period>& kept) {
    out_.max_parts = std::max(out_.max_parts, static_cast<int>(ends.size()));
    std::vector<const FlowResult*> frs;
    for (const Period& c : kept) frs.push_back(&c.fr);
    append_period_enclosures(frs, p_, k, o_.parts, spp_, out_.data.enclosures);
    std::vector<Zonotope> end_sets;
    for (const Part& e : ends) end_sets.push_back(e.z);
    Eigen::VectorXd centre;
    Fit fit = verified_set(end_sets, centre, next.lo, next.hi,
                           k + 1 < static_cast<int>(closed_.size()) ? &closed_[k + 1] : nullptr,
                           k + 1 < static_cast<int>(cost_.size()) ? &cost_[k + 1] : nullptr, o_);
    if (!fit.ok) {
      if (k + 1 == T_) {  // V_T need not be fitted: the box is checked and no input follows
        record_half_width(end_sets, next, T_);
        if (o_.keep_reach) out_.reach.push_back(std::move(end_sets));
        return Step::last;
      }
      out_.why = "no verified set fits the enclosure at step " + std::to_string(k + 1) + " (degenerate)";
      out_.reached_step = k;
      return Step::failed;
    }
    next.kind = fit.kind;
    next.c.assign(centre.data(), centre.data() + n_);  // every kind: a reduction keeps the centre
    next.S = std::move(fit.S);
    next.generators = fit.generators;
    next.tol = std::move(fit.tol);
    record_fill(end_sets, next, k + 1);
    if (o_.keep_reach) out_.reach.push_back(std::move(end_sets));
    parts_ = std::move(ends);
    return Step::next;
  }

  const TrackingProblem& p_;
  const std::vector<Eigen::MatrixXd>& K_;
  const std::vector<Eigen::MatrixXd>& closed_;
  const std::vector<Eigen::MatrixXd>& cost_;
  const VerifyOptions& o_;
  const int n_, m_, T_;
  VerifyOutcome out_;
  FlowOptions flow_;
  int spp_ = 0;  // enclosure steps per period enclosure
  std::optional<PeriodLaw> law_;  // reads out_.data and flow_, so made once both are set
  std::vector<Part> parts_;
  std::deque<Start> history_;  // the starts of the last split_lookback steps
  int rewinds_ = 0;
  double fill_sum_ = 0.0;
  int fill_count_ = 0;
};

}  // namespace

VerifyOutcome verify_funnel(const TrackingProblem& p, const std::vector<Eigen::MatrixXd>& K,
                            const std::vector<Eigen::MatrixXd>& closed, const VerifyOptions& o,
                            const std::vector<Eigen::MatrixXd>& cost) {
  const RoundToNearestScope nearest;
  return FunnelVerifier(p, K, closed, o, cost).run();
}

void make_invariant(const TrackingProblem& p, const VerifyOptions& o, VerifyOutcome& v) {
  if (!v.ok) return;
  const RoundToNearestScope nearest;
  FunnelData& d = v.data;
  std::vector<Eigen::MatrixXd> K;
  for (const auto& row : d.K) K.push_back(Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(row.data(), d.m, d.n));
  const FlowOptions flow = flow_options(p, o);
  const PeriodLaw law(p, K, d, flow, o.shift_inputs);
  v.invariant = grow_invariant_sets(p, law, d, o.parts, flow.substeps / o.parts, v.reach, o);
  v.periods += v.invariant.periods;
  d.invariant_from = v.invariant.from_step;
}

}  // namespace marsyn::funnel
