#include "invariant_sets.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>

#include <Eigen/LU>

#include "allowances.hpp"
#include "funnel_synthesis.hpp"
#include "marsyn/sampled_map.hpp"

namespace marsyn::funnel {
namespace {

using fast_detail::add_up;
using fast_detail::mul_up;

FastInterval fi(double v) { return FastInterval(v); }

Eigen::MatrixXd shape(const StepSet& s, int n) {
  Eigen::MatrixXd S(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) S(i, j) = s.S[static_cast<std::size_t>(i) * n + j];
  return S;
}

// The largest factor a by which the parallelotope's half-widths may be scaled about its centre
// with its hull inside its box (a little room left for the inverse's error): 0 if none.
double room_in_box(const StepSet& s, const Eigen::MatrixXd& M, int n) {
  double a = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) {
    const double h = M.row(i).lpNorm<1>();
    const double room = std::min(s.hi[i] - s.c[i], s.c[i] - s.lo[i]);
    if (!(room > 0) || !(h > 0)) return 0.0;
    a = std::min(a, room / h);
  }
  return a * (1 - 1e-6);
}

StepSet scaled(const StepSet& s, double a) {
  StepSet t = s;
  for (double& v : t.S) v /= a;  // the stored shape is what the argument uses, rounding and all
  return t;
}

}  // namespace

double parallelotope_row_need(const StepSet& s, int i, const std::vector<Zonotope>& parts, int n) {
  const double kappa = rounding_factor(n);
  double bound = 0.0;
  for (const Zonotope& z : parts) {
    FastInterval off(0.0);
    for (int j = 0; j < n; ++j) off += fi(s.S[static_cast<std::size_t>(i) * n + j]) * (fi(z.c[j]) - fi(s.c[j]));
    double b = mag(off);
    for (int l = 0; l < z.generators(); ++l) {
      FastInterval acc(0.0);
      for (int j = 0; j < n; ++j) acc += fi(s.S[static_cast<std::size_t>(i) * n + j]) * fi(z.G(j, l));
      b = add_up(b, mag(acc));
    }
    bound = std::max(bound, b);
  }
  return add_up(bound, parallelotope_slack(s, i, n, kappa));
}

double parallelotope_slack(const StepSet& s, int i, int n, double kappa) {
  double round = 0.0, meas = 0.0;
  for (int j = 0; j < n; ++j) {
    const double a = std::fabs(s.S[static_cast<std::size_t>(i) * n + j]);
    round = add_up(round, mul_up(a, reach(s.lo[j], s.hi[j], s.c[j])));
    meas = add_up(meas, mul_up(a, measured(s.lo[j], s.hi[j])));
  }
  return add_up(add_up(mul_up(kappa, round), kTiny), meas);
}

bool contains(const StepSet& s, const std::vector<Zonotope>& parts, int n) {
  for (const Zonotope& z : parts)
    for (int i = 0; i < n; ++i) {
      const FastInterval h = z.hull(i);
      if (!(h.lower() >= s.lo[i] && h.upper() <= s.hi[i])) return false;
    }
  if (s.kind == kBox) return true;
  if (s.kind != kParallelotope) return false;
  for (int i = 0; i < n; ++i)
    if (!(parallelotope_row_need(s, i, parts, n) <= 1.0)) return false;
  return true;
}

bool parallelotope_zonotope(const StepSet& s, int n, Zonotope& out) {
  const Eigen::MatrixXd S = shape(s, n);
  Eigen::FullPivLU<Eigen::MatrixXd> lu(S);
  if (!lu.isInvertible()) return false;
  const Eigen::MatrixXd M = lu.inverse();
  if (!M.allFinite()) return false;
  // S M = I - R with R small: then S^-1 = M (I - R)^-1, and for |y|_inf <= rmax,
  // S^-1 y = M y + M e with |e|_inf <= rho rmax / (1 - rho), rho >= ||R||_inf.
  double rho = 0.0;
  for (int i = 0; i < n; ++i) {
    double row = 0.0;
    for (int j = 0; j < n; ++j) {
      FastInterval acc(i == j ? 1.0 : 0.0);
      for (int l = 0; l < n; ++l) acc -= fi(S(i, l)) * fi(M(l, j));
      row = add_up(row, mag(acc));
    }
    rho = std::max(rho, row);
  }
  if (!(rho < 0.5)) return false;
  // An accepted state's |S_i (x - c)| is at most 1 plus the test's rounding and measurement.
  const double kappa = rounding_factor(n);
  std::vector<double> r(n);
  double rmax = 0.0;
  for (int i = 0; i < n; ++i) {
    r[i] = add_up(1.0, parallelotope_slack(s, i, n, kappa));
    rmax = std::max(rmax, r[i]);
  }
  const double e = (FastInterval(rho) * FastInterval(rmax) / (FastInterval(1.0) - FastInterval(rho))).upper();
  IVector centre(n);
  IMatrix gens(n, n);
  std::vector<double> extra(n, 0.0);
  for (int i = 0; i < n; ++i) {
    centre[i] = fi(s.c[i]);
    for (int j = 0; j < n; ++j) {
      gens(i, j) = fi(M(i, j)) * fi(r[j]);
      extra[i] = add_up(extra[i], mul_up(std::fabs(M(i, j)), e));
    }
  }
  out = from_intervals(centre, gens, extra);
  return std::isfinite(out.G.sum()) && out.c.allFinite();
}

namespace {

// The target's shape as a matrix about its centre: a parallelotope's S, or a box's scaling.
bool target_shape(const StepSet& t, int n, Eigen::MatrixXd& S, Eigen::VectorXd& c) {
  S.setZero(n, n);
  c.resize(n);
  if (t.kind == kParallelotope) {
    S = shape(t, n);
    for (int i = 0; i < n; ++i) c[i] = t.c[i];
    return true;
  }
  if (t.kind != kBox) return false;
  for (int i = 0; i < n; ++i) {
    const double h = 0.5 * (t.hi[i] - t.lo[i]);
    if (!(h > 0)) return false;
    S(i, i) = 1.0 / h;
    c[i] = 0.5 * t.lo[i] + 0.5 * t.hi[i];
  }
  return true;
}

// The closed loop's linearization over step k at the nominal: A + B K_k of the RK4 map.
Eigen::MatrixXd closed_loop(const TrackingProblem& p, const FunnelData& d, int k) {
  const int n = d.n, m = d.m;
  std::vector<double> A(static_cast<std::size_t>(n) * n), B(static_cast<std::size_t>(n) * m);
  rk4_jacobians(*p.dynamics, d.x_nom[static_cast<std::size_t>(k)].data(), d.u_nom[static_cast<std::size_t>(k)].data(), p.tau, 8,
                nullptr, A.data(), B.data());
  const auto Am = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(A.data(), n, n);
  const auto Bm = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(B.data(), n, m);
  const auto Km = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      d.K[static_cast<std::size_t>(k)].data(), m, n);
  return Am + Bm * Km;
}

// The parallelotope {x in s's box : |diag(1 / e) S (x - c)|_inf <= 1} about s's centre (row i of
// S scaled to the extent e_i), shrunk until its hull lies in the box: the controller tests both,
// so a parallelotope past its box only loosens the period's start and makes a poorer target.
StepSet with_rows(const StepSet& s, const Eigen::MatrixXd& S, const Eigen::VectorXd& e) {
  StepSet t = s;
  const int n = static_cast<int>(S.rows());
  t.kind = kParallelotope;
  t.S.resize(static_cast<std::size_t>(n) * n);
  Eigen::MatrixXd R(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) R(i, j) = S(i, j) / e[i];
  Eigen::FullPivLU<Eigen::MatrixXd> lu(R);
  if (lu.isInvertible()) {
    const double a = room_in_box(s, lu.inverse(), n);
    if (a > 0 && a < 1) R /= a;
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) t.S[static_cast<std::size_t>(i) * n + j] = R(i, j);
  return t;
}

// A box's data with c set (a box has none stored).
StepSet centred(const StepSet& box, const Eigen::VectorXd& c) {
  StepSet t = box;
  t.c.assign(c.data(), c.data() + c.size());
  return t;
}

// One step of the backward pass: the largest candidate V_k (containing what step k must hold)
// whose period ends in V_{k+1} for every state it accepts. Candidates: the forward set scaled up
// toward its box, then the target's shape pulled back through the closed loop's linearization
// (the set the linear part maps onto the target), scaled between what contains `must` and its
// box. Any candidate is sound: the period from it is enclosed and its end checked in interval
// arithmetic; the shapes are only guesses.
class StepGrower {
 public:
  StepGrower(const TrackingProblem& p, const PeriodLaw& law, FunnelData& d, int parts, int spp, InvariantOutcome& out)
      : p_(p), law_(law), d_(d), parts_(parts), spp_(spp), out_(out), n_(d.n) {}

  // The accepted candidate's width relative to the forward set (the n-th root of their volumes'
  // ratio; 1: the forward set itself), or 0 when none is invariant.
  double grow(int k, const std::vector<Zonotope>& must) {
    const StepSet s = d_.sets[static_cast<std::size_t>(k)];  // the forward set (accept() overwrites the stored one)
    const StepSet& target = d_.sets[static_cast<std::size_t>(k) + 1];
    const Eigen::MatrixXd Sf = shape(s, n_);
    const double forward_det = std::fabs(Sf.determinant());
    if (!(forward_det > 0) || !std::isfinite(forward_det)) return 0.0;
    auto width = [&](const StepSet& c) { return std::pow(forward_det / std::fabs(shape(c, n_).determinant()), 1.0 / n_); };
    if (const double a = scale_forward(k, s, must); a > 0) return a;
    // The target's shape pulled back: row i of S_t Phi (x - c) is, to first order, row i of the
    // target's test at the period's end, so each row may take what the target's row has left.
    Eigen::MatrixXd St;
    Eigen::VectorXd ct;
    if (!target_shape(target, n_, St, ct)) return 0.0;
    const Eigen::MatrixXd Sp = St * closed_loop(p_, d_, k);
    if (!Sp.allFinite() || !(std::fabs(Sp.determinant()) > 0)) return 0.0;
    StepSet unit = with_rows(s, Sp, Eigen::VectorXd::Ones(n_));
    Eigen::VectorXd tight(n_);  // per row, the least extent holding `must`
    for (int i = 0; i < n_; ++i) tight[i] = parallelotope_row_need(unit, i, must, n_) * (1 + 1e-9);
    if (!tight.allFinite() || !(tight.minCoeff() > 0)) return 0.0;
    const StepSet cand = with_rows(s, Sp, tight);
    Eigen::VectorXd room;
    if (!accept(k, cand, target, must, &room)) return 0.0;
    for (double g : {0.6, 0.2}) {
      const StepSet wider = with_rows(s, Sp, tight + g * room);
      if (accept(k, wider, target, must, nullptr)) return width(wider);
    }
    return width(cand);
  }

  // In an invariant chain: V_k scaled up toward its box as far as its period still ends in V_{k+1}
  // (tried largest first; the set as it is, 1, is invariant already and kept otherwise).
  double scale_up(int k, const std::vector<Zonotope>& must) {
    const StepSet s = d_.sets[static_cast<std::size_t>(k)];
    if (s.kind != kParallelotope) return 1.0;  // a zonotope's image has no containment test here
    const double a = scale_toward_box(k, s, must, {1.0, 0.3});
    return a > 0 ? a : 1.0;
  }

  // The forward set scaled about its centre toward its box, largest first, itself last; 0 when
  // none fits.
  double scale_forward(int k, const StepSet& s, const std::vector<Zonotope>& must) {
    return scale_toward_box(k, s, must, {1.0, 0.25, 0.0});
  }

 private:
  // s scaled by 1 + f (top - 1) for each fraction f in turn, top the scale that reaches its box
  // (f = 0: s itself); the first that accept() takes as V_k, or 0.
  double scale_toward_box(int k, const StepSet& s, const std::vector<Zonotope>& must, std::initializer_list<double> fractions) {
    Eigen::FullPivLU<Eigen::MatrixXd> lu(shape(s, n_));
    if (!lu.isInvertible()) return 0.0;
    const double top = room_in_box(s, lu.inverse(), n_);
    const StepSet& target = d_.sets[static_cast<std::size_t>(k) + 1];
    for (double f : fractions) {
      if (f > 0 && !(top > 1.0)) continue;
      const double a = 1.0 + f * (top - 1.0);
      if (accept(k, f > 0 ? scaled(s, a) : s, target, must, nullptr)) return a;
    }
    return 0.0;
  }

  // cand as V_k if it holds `must` and its period ends in the target; then its period
  // enclosures replace step k's. room (may be null): per target row, 1 minus the end's need.
  bool accept(int k, const StepSet& cand, const StepSet& target, const std::vector<Zonotope>& must, Eigen::VectorXd* room) {
    // The guarantee from the initial set needs the reachable set inside (the scaled shape is
    // rounded, and the pulled-back one is new): checked, not assumed.
    if (!contains(cand, must, n_)) return false;
    Zonotope start;
    if (!parallelotope_zonotope(cand, n_, start)) return false;
    Period q = law_.with_input(start, k, d_.u_nom[static_cast<std::size_t>(k)]);
    ++out_.periods;
    if (!q.fr.ok) return false;
    Zonotope end;
    end.c = q.fr.end.c.head(n_);
    end.G = q.fr.end.G.topRows(n_);
    if (!contains(target, {end}, n_)) return false;
    if (room) {
      // The target as a parallelotope test (a box: its own scaling), row by row.
      Eigen::MatrixXd St;
      Eigen::VectorXd ct;
      target_shape(target, n_, St, ct);
      const StepSet t = with_rows(target.kind == kParallelotope ? target : centred(target, ct), St, Eigen::VectorXd::Ones(n_));
      room->resize(n_);
      for (int i = 0; i < n_; ++i) (*room)[i] = std::max(0.0, 1.0 - parallelotope_row_need(t, i, {end}, n_));
    }
    std::vector<PeriodEnclosure> encl;
    append_period_enclosures({&q.fr}, p_, k, parts_, spp_, encl);
    for (int part = 0; part < parts_; ++part) d_.enclosures[static_cast<std::size_t>(k) * parts_ + part] = std::move(encl[part]);
    d_.sets[static_cast<std::size_t>(k)] = cand;
    return true;
  }

  const TrackingProblem& p_;
  const PeriodLaw& law_;
  FunnelData& d_;
  const int parts_, spp_;
  InvariantOutcome& out_;
  const int n_;
};

}  // namespace

namespace {


// V_0 as the period's start: the initial box with the measured state's allowance.
Zonotope initial_zonotope(const StepSet& s0, int n) {
  IVector c(n);
  std::vector<double> meas(n);
  for (int i = 0; i < n; ++i) {
    c[i] = FastInterval(s0.lo[i], s0.hi[i]);
    meas[i] = measured(s0.lo[i], s0.hi[i]);
  }
  return from_intervals(c, IMatrix(n, 0), meas);
}

// Sets invariant by construction, forward from V_0: V_{k+1} is fitted around the period's end
// from V_k itself, so every state V_k accepts reaches V_{k+1}; by induction from V_0 they hold
// every state reachable from the initial set.
// False when some end leaves its box or no parallelotope holds it; d is then partly rewritten
// (the caller restores it).
// order: 0 for parallelotopes, else the zonotopes' generators per state.
// floor: each fitted set is first widened to at least that fraction of eps about its centre in
// every coordinate (the end of the period plus a box), so that the chain's sets are as wide as the
// tube allows the feedback to hold, not only as wide as the reachable set.
bool forward_chain(const TrackingProblem& p, const PeriodLaw& law, FunnelData& d, int parts, int spp, const VerifyOptions& o,
                   int order, double floor, InvariantOutcome& out) {
  const int n = d.n, T = d.horizon();
  for (int k = 0; k < T; ++k) {
    const StepSet& s = d.sets[static_cast<std::size_t>(k)];
    Zonotope start;
    if (k == 0) {
      start = initial_zonotope(s, n);
    } else if (!accepted_zonotope(s, n, start)) {
      return false;
    }
    const Period q = law.with_input(start, k, d.u_nom[static_cast<std::size_t>(k)]);
    ++out.periods;
    if (!q.fr.ok) return false;
    std::vector<Zonotope> held(1);
    held[0].c = q.fr.end.c.head(n);
    held[0].G = q.fr.end.G.topRows(n);
    StepSet& next = d.sets[static_cast<std::size_t>(k) + 1];
    for (int i = 0; i < n; ++i) {
      const FastInterval h = held[0].hull(i);
      if (!(h.lower() >= next.lo[i] && h.upper() <= next.hi[i])) return false;
    }
    if (k + 1 < T) {
      if (floor > 0) {
        std::vector<double> widen(n, 0.0);
        for (int i = 0; i < n; ++i) widen[i] = std::max(0.0, floor * p.tube.eps[i] - held[0].radius(i));
        Zonotope wide = held[0];
        append_box(wide, widen);
        for (int i = 0; i < n; ++i) {  // clipped to what the box leaves: the controller tests both
          const FastInterval h = wide.hull(i);
          if (h.lower() < next.lo[i] || h.upper() > next.hi[i]) widen[i] = 0.0;
        }
        append_box(held[0], widen);
      }
      const Eigen::MatrixXd closed = closed_loop(p, d, k + 1);
      if (order > 0 ? !fit_zonotope(held[0], order, next)
                    : !fit_parallelotope(held, next, closed.allFinite() ? &closed : nullptr, nullptr, o) || !contains(next, held, n))
        return false;
    }
    std::vector<PeriodEnclosure> encl;
    append_period_enclosures({&q.fr}, p, k, parts, spp, encl);
    for (int part = 0; part < parts; ++part) d.enclosures[static_cast<std::size_t>(k) * parts + part] = std::move(encl[part]);
  }
  return true;
}

}  // namespace

bool accepted_zonotope(const StepSet& s, int n, Zonotope& out) {
  if (s.kind == kParallelotope) return parallelotope_zonotope(s, n, out);
  if (s.kind != kZonotope) return false;
  const int p = s.generators;
  // The test accepts x when some |xi| <= 1 leaves |fl(sum_j G_ij xi_j - fl(x_i - c_i))| <= tol_i:
  // the sum's rounding is at most kappa (|x_i - c_i| + sum_j |G_ij|), the difference's u |x_i -
  // c_i|, and the real state is within the measured allowance of the double the test reads.
  const double kappa = rounding_factor(p + 1);
  IVector centre(n);
  IMatrix gens(n, p);
  std::vector<double> extra(n);
  for (int i = 0; i < n; ++i) {
    centre[i] = fi(s.c[i]);
    const double D = reach(s.lo[i], s.hi[i], s.c[i]);
    double g = 0.0;
    for (int j = 0; j < p; ++j) {
      const double v = s.S[static_cast<std::size_t>(j) * n + i];
      gens(i, j) = fi(v);
      g = add_up(g, std::fabs(v));
    }
    extra[i] = add_up(add_up(add_up(s.tol[i], mul_up(kappa, add_up(D, g))), mul_up(0x1p-53, D)),
                      add_up(measured(s.lo[i], s.hi[i]), kTiny));
  }
  out = from_intervals(centre, gens, extra);
  return out.c.allFinite() && out.G.allFinite();
}

InvariantOutcome grow_invariant_sets(const TrackingProblem& p, const PeriodLaw& law, FunnelData& d, int parts, int spp,
                                     const std::vector<std::vector<Zonotope>>& reach, const VerifyOptions& o) {
  const int n = d.n, T = d.horizon();
  InvariantOutcome out;
  // At T no input follows and the guarantee is the tube's box itself: the largest target.
  StepSet& last = d.sets[static_cast<std::size_t>(T)];
  last.kind = kBox;
  last.c.clear();
  last.S.clear();
  last.generators = 0;
  last.tol.clear();
  out.from_step = T;
  StepGrower grower(p, law, d, parts, spp, out);
  const std::vector<StepSet> sets = d.sets;
  const std::vector<PeriodEnclosure> enclosures = d.enclosures;
  // Parallelotopes first (one O(n^2) test per call), then zonotopes of growing order (the
  // membership test's cost grows with it), unless the stored sets are to be zonotopes of the
  // user's order.
  std::vector<int> orders = {0, 2, kChainOrder};
  if (o.zonotope_sets) orders = {o.set_order};
  // Each order widened to a quarter of eps first (the sets as wide as the feedback holds them,
  // in one pass where it does), then as the chain gives them. Half of eps held less often on the
  // examples and cost a whole failing chain where it did not.
  bool chained = false;
  for (const int order : orders) {
    for (const double floor : {0.25, 0.0}) {
      d.sets = sets;
      d.enclosures = enclosures;
      if ((chained = forward_chain(p, law, d, parts, spp, o, order, floor, out))) {
        out.order = order;
        out.floor = floor;
        break;
      }
    }
    if (chained) break;
  }
  if (chained) {
    // Invariant at every step; growing V_k (last first) keeps it so, each set's period checked
    // against its successor as grown. Not after the widening held: that chain's sets span a
    // quarter of eps already, and growing costs up to two more periods per step.
    out.from_step = 0;
    double scale_sum = 0.0;
    for (int k = T - 1; k >= 1 && out.floor == 0.0; --k) {
      const double a = grower.scale_up(k, reach.size() > static_cast<std::size_t>(k) ? reach[static_cast<std::size_t>(k)] : std::vector<Zonotope>{});
      out.grown += a > 1.0;
      scale_sum += a;
    }
    out.mean_scale = T > 1 ? scale_sum / (T - 1) : 1.0;
    return out;
  }
  d.sets = sets;
  d.enclosures = enclosures;
  double scale_sum = 0.0;
  int scale_count = 0;
  for (int k = T - 1; k >= 1; --k) {
    const StepSet& s = d.sets[static_cast<std::size_t>(k)];
    if (s.kind != kParallelotope) break;
    // What V_k must hold: the reachable set where the verification kept it, else the forward set.
    std::vector<Zonotope> must;
    if (static_cast<int>(reach.size()) > k) {
      must = reach[static_cast<std::size_t>(k)];
    } else {
      Zonotope z;
      if (!parallelotope_zonotope(s, n, z)) break;
      must.push_back(std::move(z));
    }
    const double a = grower.grow(k, must);
    if (!(a > 0)) break;
    out.grown += a > 1.0;
    scale_sum += a;
    ++scale_count;
    out.from_step = k;
  }
  // V_0 is the initial box: its every run lies in the reachable set of step 1, which V_1 contains
  // (it holds the reachable set or the forward set), and step 0's enclosures are V_0's own.
  if (out.from_step == 1) out.from_step = 0;
  out.mean_scale = scale_count ? scale_sum / scale_count : 1.0;
  return out;
}

}  // namespace marsyn::funnel
