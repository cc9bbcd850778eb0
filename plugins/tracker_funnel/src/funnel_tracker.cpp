#include "funnel_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include <Eigen/LU>

#include "input_weights.hpp"
#include "invariant_sets.hpp"
#include "lqr.hpp"
#include "tightness.hpp"
#include "marsyn/dual.hpp"
#include "marsyn/number_text.hpp"
#include "marsyn/param_set.hpp"
#include "marsyn/stopwatch.hpp"

namespace marsyn::funnel {
namespace {

// When the configured weights give no verified funnel, these multiples of the input weight are
// tried in turn: stiffer feedback (smaller R) contracts more, softer saturates less.
constexpr double kInputWeightLadder[] = {1.0, 0.1, 10.0, 0.01, 100.0};
constexpr int kFirstReachOrder = 8;
constexpr double kRoomyFill = 0.25;

// What the controller's acceptance means: the guarantee from every accepted state (invariant
// sets), from some step on, or only for what the initial set reaches.
// Per coordinate the largest |x_i - x_k,i| / scale_i over the verified sets of the steps reached
// (TrackFailure::tube_use with scale eps, TrackerStats::tube_kept with 1).
std::vector<double> tube_use(const std::vector<std::vector<double>>& half_width, const Eigen::VectorXd& eps) {
  std::vector<double> use(static_cast<std::size_t>(eps.size()), 0.0);
  for (const auto& hw : half_width)
    for (std::size_t i = 0; i < use.size() && i < hw.size(); ++i) use[i] = std::max(use[i], hw[i] / eps[static_cast<Eigen::Index>(i)]);
  return use;
}

// What the outer search reads of a miss (TrackFailure): where, by how much, how near its edge
// every coordinate came, how often inputs saturated.
TrackFailure failure_of(const VerifyOutcome& best, const Eigen::VectorXd& eps) {
  TrackFailure f;
  if (best.miss_coordinate >= 0) {
    f.kind = TrackFailureKind::TubeMiss;
    f.coordinate = best.miss_coordinate;
    f.step = best.reached_step + 1;
    f.amount = best.miss_amount;
    f.off_centre = best.miss_off_centre;
    f.tube_use = tube_use(best.half_width, eps);
    auto& missed = f.tube_use[static_cast<std::size_t>(best.miss_coordinate)];
    missed = std::max(missed, 1.0 + best.miss_amount / eps[best.miss_coordinate]);
  }
  if (best.reached_step > 0) f.input_saturation = static_cast<double>(best.saturated_steps) / best.reached_step;
  return f;
}

std::string invariance_text(const FunnelData& d, const InvariantOutcome& inv, bool asked) {
  const int T = d.horizon();
  std::ostringstream t;
  t.precision(3);
  if (!asked || d.invariant_from >= T) {
    t << "verified sets hold what the initial set reaches, not invariant"
      << (asked ? " (V_" + std::to_string(T - 1) + " maps outside V_" + std::to_string(T) + ")" : std::string(" (invariant_sets: false)"));
    return t.str();
  }
  if (d.invariant_from == 0 && inv.order > 0)
    t << "verified sets invariant at every step (zonotopes of up to " << inv.order << " n generators)";
  else if (d.invariant_from == 0)
    t << "verified sets invariant at every step";
  else
    t << "verified sets invariant from step " << d.invariant_from << " of " << T << " (before it they hold what the initial set reaches: V_"
      << d.invariant_from - 1 << " maps outside V_" << d.invariant_from << ")";
  if (inv.grown) t << ", " << inv.grown << " grown toward the tube (x" << inv.mean_scale << " on average)";
  return t.str();
}

// Per coordinate, the smallest over steps 1 .. T - 1 of the accepted set's half-width (its hull
// within its box) relative to eps: how large an error the controller tolerates everywhere.
std::vector<double> narrowest_accepted(const FunnelData& d) {
  const int n = d.n, T = d.horizon();
  std::vector<double> out(n, std::numeric_limits<double>::infinity());
  for (int k = 1; k < T; ++k) {
    const StepSet& s = d.sets[static_cast<std::size_t>(k)];
    Eigen::MatrixXd G;
    if (s.kind == kZonotope) {
      G = Eigen::Map<const Eigen::MatrixXd>(s.S.data(), n, s.generators);
    } else if (s.kind == kParallelotope) {
      G = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(s.S.data(), n, n).inverse();
    }
    for (int i = 0; i < n; ++i) {
      double lo = s.lo[i], hi = s.hi[i];
      if (G.size()) {
        const double r = G.row(i).lpNorm<1>();
        lo = std::max(lo, s.c[i] - r);
        hi = std::min(hi, s.c[i] + r);
      }
      out[i] = std::min(out[i], 0.5 * (hi - lo) / d.eps[i]);
    }
  }
  return out;
}

// The stored sets' kinds, what accepting a state means (invariance_text) and how far the accepted
// sets reach in every coordinate.
std::string sets_text(const FunnelData& d, const InvariantOutcome& inv, bool asked, const std::vector<std::string>& names) {
  std::ostringstream t;
  t.precision(3);
  int kinds[3] = {0, 0, 0};
  for (const StepSet& st : d.sets) ++kinds[std::min<int>(st.kind, 2)];
  t << "sets: " << kinds[1] << " parallelotopes, " << kinds[2] << " zonotopes; " << invariance_text(d, inv, asked);
  if (d.horizon() > 1) {
    const std::vector<double> w = narrowest_accepted(d);
    t << "; accepted sets at least";
    for (std::size_t i = 0; i < w.size(); ++i) t << (i ? ", " : " ") << names[i] << " +-" << 100 * w[i] << "%";
    t << " of eps";
  }
  return t.str();
}

// A weight: positive and finite, checked as soon as it is read.
void weight(ParamSet<Options>& s, std::string name, double Options::*member, std::string doc) {
  s.add(std::move(name), member, "(0, inf)", std::move(doc))
      .require({[](const double& v) { return v > 0 && std::isfinite(v); }, "expected a positive number"});
}

ParamSet<Options> declare() {
  using O = Options;
  ParamSet<O> s;
  s.integer("substeps", 1, 1024,
            "enclosure steps per sampling period, a multiple of enclosure_substeps (more: tighter, slower)",
            Checked::on_read, &O::substeps);
  // Reported under substeps, right after enclosure_substeps is read.
  s.integer("enclosure_substeps", 1, 64,
            "boxes per sampling period enclosing the closed loop between samples (continuous-time guarantee)",
            Checked::on_read, &O::parts)
      .check([](const O& o) {
        if (o.substeps % o.parts != 0)
          throw ParamError("substeps", "expected a multiple of enclosure_substeps (" + std::to_string(o.parts) + "), got " +
                                           std::to_string(o.substeps));
      });
  s.integer("picard_iterations", 1, 100, "a priori enclosure attempts per enclosure step", Checked::on_read,
            &O::picard_iterations);
  s.integer("max_generators", 0, 1000,
            "zonotope generators kept within a period; 0: reach_order n + n + m, after a cheap pass at 8 n + n + m; "
            "a number: that many, in one pass",
            Checked::on_read, &O::max_generators);
  s.integer(
      "reach_order", 1, 64,
      "generators per state of the reachable-set enclosure carried from period to period (more: tighter, slower); "
      "above 8, a pass at 8 goes first and is kept if its sets fill at most 25% of eps",
      Checked::on_read, &O::reach_order);
  // Its length (the state dimension) is checked per agent (assess, track).
  s.add("initial_radius", &O::initial_radius, "[0, eps)",
        "half-widths of the initial box around x0 (one per state); empty: initial_fraction x eps")
      .listed_as("0.1 eps")
      .require({[](const std::vector<double>& radii) {
                  for (double r : radii)
                    if (!(r >= 0) || !std::isfinite(r)) return false;
                  return true;
                },
                "expected non-negative numbers"});
  s.add("initial_fraction", &O::initial_fraction, "[0, 1)", "initial box half-width as a fraction of eps")
      .require({[](const double& v) { return v >= 0 && v < 1; }, "expected a number in [0, 1)"});
  weight(s, "state_weight", &O::state_weight, "LQR state weight, times 1 / eps_i^2 (Bryson's rule)");
  weight(s, "input_weight", &O::input_weight, "LQR input weight, times 1 / (half the input range)^2 (Bryson's rule)");
  weight(s, "terminal_weight", &O::terminal_weight, "terminal cost P_T = terminal_weight Q");
  s.add("weight_search", &O::weight_search, "true|false",
        "when the weights give no verified funnel, try input weights x 0.1, 10, 0.01, 100 in turn");
  s.integer("rk4_substeps", 1, 1000, "RK4 substeps of the sampled map linearized for the gains", Checked::on_read,
            &O::rk4_substeps);
  s.add("enclosure", &O::enclosure, "second_order|mean_value",
        "linearization error of the flow enclosure: Lagrange remainder with interval Hessians (per row the smaller "
        "of it and the mean-value bound), or the mean-value (Jacobian spread) bound alone")
      .require({[](const std::string& v) { return v == "second_order" || v == "mean_value"; },
                "expected second_order or mean_value"});
  s.add("verified_set", &O::verified_set, "parallelotope|zonotope",
        "the stored set V_k the controller tests: a parallelotope (one O(n^2) test) or a zonotope of order "
        "set_order (tighter; a small simplex at worst)")
      .require({[](const std::string& v) { return v == "parallelotope" || v == "zonotope"; },
                "expected parallelotope or zonotope"});
  s.integer("set_order", 2, 8, "zonotope order (generators / n) of verified_set: zonotope", Checked::on_read,
            &O::set_order);
  s.integer("box_substeps", 0, 1024,
            "enclosure steps after which the box of new errors becomes zonotope generators; 0: once per period",
            Checked::on_read, &O::box_substeps);
  s.add("shift_inputs", &O::shift_inputs, "true|false",
        "where u_k + K (x - x_k) leaves U over the verified set but fits in it, also try the law with u_k moved "
        "inside U (an offset instead of saturation) and keep the period that ends closer inside the tube");
  s.add("invariant_sets", &O::invariant_sets, "true|false",
        "after the verification, grow each verified set V_k (last step first) as far toward its box inside the "
        "tube as keeps it invariant: every state it accepts reaches V_{k+1} for every disturbance, so the "
        "controller and its monitor accept exactly states with the guarantee from there on; false: V_k only "
        "contains the states reached from the initial set");
  s.integer("split_depth", 0, 8,
            "times a part of the carried set that misses the tube may be split in two along its widest generator "
            "and verified again (at most 2^split_depth parts; the controller is unchanged); 0: never",
            Checked::on_read, &O::split_depth);
  s.integer("input_rounds", 0, 8,
            "when a weight choice misses with some input enclosed saturated (past U by over 1% of its width), "
            "redesign its gains (once per agent) up to this many times with R raised where the input hull left U "
            "(input-aware weights); 0: never",
            Checked::on_read, &O::input_rounds);
  s.integer("tightness_runs", 0, 100000,
            "sampled closed-loop runs measuring verified half-width / largest deviation seen (a statistic; 0: off)",
            Checked::on_read, &O::tightness_runs);
  return s;
}

}  // namespace

FunnelTracker::FunnelTracker(const Params& p) : s_(declared_once<declare>().parse(p)) {}

std::vector<ParamSpec> FunnelTracker::param_specs() { return declared_once<declare>().specs(); }

TrackerAssessment FunnelTracker::assess(const AgentSpec& a, int horizon, double tau) const {
  TrackerAssessment r;
  const int n = a.n(), m = a.m();
  if (n + m > kMaxDual) {
    r.ok = false;
    r.field = "dynamics";
    r.message = "the funnel tracker handles agents with states + inputs <= " + std::to_string(kMaxDual) + ", this one has " +
                std::to_string(n + m);
    return r;
  }
  if (!s_.initial_radius.empty() && static_cast<int>(s_.initial_radius.size()) != n) {
    r.ok = false;
    r.field = "initial_radius";
    r.message = "expected " + std::to_string(n) + " numbers (one per state), got " + std::to_string(s_.initial_radius.size());
    return r;
  }
  const Eigen::VectorXd r0 = initial_box(a.tube.eps, a.x0_radius);
  for (int i = 0; i < n; ++i) {
    if (i == uncovered_coordinate(a.x0_radius)) {
      r.ok = false;
      r.field = "initial_radius";
      r.coordinate = i;
      r.message = "the initial box (half-width " + number_text(s_.initial_radius[i]) +
                  ") must hold the problem's stated initial set (x0_radius " + number_text(a.x0_half(i)) + ")";
      return r;
    }
    if (!(r0[i] < a.tube.eps[i])) {
      r.ok = false;
      r.field = "initial_radius";
      r.coordinate = i;
      r.message = "the initial box (half-width " + number_text(r0[i]) + ") must lie strictly inside the eps-box (eps " +
                  number_text(a.tube.eps[i]) + ")";
      return r;
    }
  }
  // Per enclosure step: two Jacobians over n + m directions and a zonotope product of about
  // n x (n + m) x p operations (p = the first pass's carried generators, order n + n + m), ~2 ns
  // each; a few weight choices in the worst case.
  const double N = n + m;
  const long first_order = s_.reach_order > kFirstReachOrder ? kFirstReachOrder : s_.reach_order;
  const double p = static_cast<double>(s_.max_generators > 0 ? s_.max_generators : first_order * n + N);
  const double per_step = 2e-9 * (n * N * p + 40 * N * N);
  const double tries = s_.weight_search ? 3 : 1;
  r.work_s = tries * std::max(1, horizon) * s_.substeps * per_step;
  // Kept: the controller (funnel_controller.hpp). Working: the funnel being built beside the best
  // so far, the reachable set carried per step for the invariant sets (zonotopes of up to
  // reach_order n generators), and the recursion's matrices.
  const double steps = std::max(1, horizon);
  // Sets: zonotopes of set_order n generators, or the invariant chain's fallback of order 8.
  const int set_generators = static_cast<int>(std::max<long>(s_.set_order, kChainOrder)) * n;
  r.kept_bytes = kept_bytes_bound(n, m, horizon, static_cast<int>(s_.parts), set_generators);
  r.memory_bytes = 2 * r.kept_bytes + 8.0 * (steps + 1) * n * (static_cast<double>(s_.reach_order) * n + 1) +
                   8.0 * steps * (3.0 * n * n + 4.0 * n + m * n + s_.parts * (2.0 * n + 4));
  std::ostringstream s;
  s.precision(kMessageDigits);
  s << "LQR funnel, " << s_.substeps << " enclosure steps per period of " << tau << " s, initial box ";
  if (!s_.initial_radius.empty()) s << "as configured";
  else if (a.x0_radius.size() > 0) s << "the stated initial set (x0_radius)";
  else s << s_.initial_fraction << " eps";
  r.summary = s.str();
  return r;
}

bool FunnelTracker::refine(AgentSpec& a) const {
  // Tighter enclosures first (the verification's own error), then stiffer feedback.
  Params& p = a.tracker.params;
  const long order = p.integer("reach_order", s_.reach_order);
  if (order < 64) {
    p.set("reach_order", std::min<long>(64, order * 2));
    return true;
  }
  const long sub = p.integer("substeps", s_.substeps);
  if (sub * 2 <= 256) {
    p.set("substeps", sub * 2);
    return true;
  }
  const double q = p.real("state_weight", s_.state_weight);
  if (q * 4 <= 1e4) {
    p.set("state_weight", q * 4);
    return true;
  }
  return false;
}

std::vector<TrackerLever> FunnelTracker::levers(const AgentSpec& a) const {
  std::vector<TrackerLever> out;
  const std::vector<TrackFailureKind> kinds{TrackFailureKind::TubeMiss, TrackFailureKind::Unknown};
  for (const auto& [name, cost] : {std::pair{"more enclosure generators", 2.0}, std::pair{"more enclosure substeps", 2.0},
                                    std::pair{"stiffer feedback", 1.0}}) {
    AgentSpec b = a;
    if (apply_lever(name, {}, b)) out.push_back({name, kinds, cost});
  }
  return out;
}

bool FunnelTracker::apply_lever(const std::string& name, const TrackFailure& failure, AgentSpec& a) const {
  (void)failure;
  Params& p = a.tracker.params;
  if (name == "more enclosure generators") {
    const long order = p.integer("reach_order", s_.reach_order);
    if (order >= 64) return false;
    p.set("reach_order", std::min<long>(64, order * 2));
    return true;
  }
  if (name == "more enclosure substeps") {
    const long sub = p.integer("substeps", s_.substeps);
    if (sub * 2 > 256) return false;
    p.set("substeps", sub * 2);
    return true;
  }
  if (name == "stiffer feedback") {
    const double q = p.real("state_weight", s_.state_weight);
    if (q * 4 > 1e4) return false;
    p.set("state_weight", q * 4);
    return true;
  }
  return name == "refine" && refine(a);
}

int FunnelTracker::uncovered_coordinate(const Eigen::VectorXd& stated) const {
  if (s_.initial_radius.empty()) return -1;
  for (Eigen::Index i = 0; i < stated.size() && i < static_cast<Eigen::Index>(s_.initial_radius.size()); ++i)
    if (!(s_.initial_radius[static_cast<std::size_t>(i)] >= stated[i])) return static_cast<int>(i);
  return -1;
}

Eigen::VectorXd FunnelTracker::initial_box(const Eigen::VectorXd& eps, const Eigen::VectorXd& stated) const {
  Eigen::VectorXd r(eps.size());
  for (Eigen::Index i = 0; i < eps.size(); ++i)
    r[i] = !s_.initial_radius.empty() ? s_.initial_radius[static_cast<std::size_t>(i)]
           : stated.size() > 0        ? (i < stated.size() ? stated[i] : 0.0)
                                      : s_.initial_fraction * eps[i];
  return r;
}

VerifyOptions FunnelTracker::verify_options(const Eigen::VectorXd& eps, const Eigen::VectorXd& stated) const {
  VerifyOptions vo;
  vo.flow.substeps = s_.substeps;
  vo.flow.picard_iterations = s_.picard_iterations;
  vo.flow.max_generators = s_.max_generators;
  vo.flow.remainder_scale = remainder_scale_;
  vo.flow.remainder = s_.enclosure == "mean_value" ? Remainder::MeanValue : Remainder::SecondOrder;
  vo.parts = s_.parts;
  vo.set_order = static_cast<int>(s_.set_order);
  vo.reach_order = static_cast<int>(s_.reach_order);
  vo.zonotope_sets = s_.verified_set == "zonotope";
  vo.keep_reach = reach_out_ != nullptr || s_.invariant_sets;  // the invariant sets must keep holding them
  vo.shift_inputs = s_.shift_inputs;
  vo.flow.box_substeps = static_cast<int>(s_.box_substeps);
  vo.split_depth = static_cast<int>(s_.split_depth);
  vo.initial_radius = initial_box(eps, stated);
  return vo;
}

// search's run: the input weights of the ladder in turn, each with the cheap pass first; the
// first verified funnel, or the one that got furthest.
class FunnelTracker::Ladder {
 public:
  Ladder(const FunnelTracker& tracker, const TrackingProblem& p, const std::function<bool()>& stop)
      : s_(tracker.s_), p_(p), vo_(tracker.verify_options(p.tube.eps, p.initial_radius)) {
    vo_.stop = stop;
  }

  Search run() {
    const int n = p_.dynamics->state_dim(), m = p_.dynamics->input_dim();
    LqrWeights wt;
    wt.q.resize(n);
    wt.r.resize(m);
    for (int i = 0; i < n; ++i) wt.q[i] = s_.state_weight / (p_.tube.eps[i] * p_.tube.eps[i]);
    wt.terminal = s_.terminal_weight;
    const int tries = s_.weight_search ? static_cast<int>(std::size(kInputWeightLadder)) : 1;
    best().reached_step = -1;
    // A cheap pass first: carried at order kFirstReachOrder the enclosure verifies most agents of
    // large teams (the circle swaps' unicycles fill 14% of eps either way) at about half the cost.
    // Where it misses, or its sets fill more than kRoomyFill of eps, the same gains again at
    // reach_order. An explicit max_generators keeps one pass.
    orders_ = {static_cast<int>(s_.reach_order)};
    if (s_.reach_order > kFirstReachOrder && s_.max_generators == 0) orders_.insert(orders_.begin(), kFirstReachOrder);
    out_.order = orders_.back();
    // Splitting (split_depth) is a second chance: the ladder runs without it, so that what
    // verifies without splits costs what it did; then the gains that got furthest are verified
    // again with splits, once.
    const int split_depth = vo_.split_depth;
    vo_.split_depth = 0;
    // Input-aware rounds go to the first weight choice whose furthest pass enclosed some input
    // as a saturated box (one agent pays for at most input_rounds more designs).
    bool rounds_left = s_.input_rounds > 0;
    for (int t = 0; t < tries && !out_.stopped; ++t) {
      for (int j = 0; j < m; ++j) {
        const double half = 0.5 * (p_.input_bounds.hi[j] - p_.input_bounds.lo[j]);
        wt.r[j] = s_.input_weight * kInputWeightLadder[t] / (half > 0 ? half * half : 1.0);
      }
      wt.r_steps.clear();
      LqrGains g = design(wt);
      if (!g.ok()) continue;
      ++out_.weight_choices;
      VerifyOutcome last;
      if (verify_gains(g, last, orders_, true) && !best().ok) furthest_ = g;
      if (!best().ok && !cheap_.ok && rounds_left && saturation_matters(p_, last)) {
        rounds_left = false;
        input_aware_rounds(std::move(g), last, wt);
      }
      if (best().ok) break;
      if (cheap_.ok) {
        best() = std::move(cheap_);
        out_.order = kFirstReachOrder;
        break;
      }
    }
    if (!best().ok && !out_.stopped && split_depth > 0 && furthest_.ok()) verify_with_splits(split_depth);
    return std::move(out_);
  }

 private:
  VerifyOutcome& best() { return out_.best; }

  LqrGains design(const LqrWeights& w) {
    const Stopwatch tg;
    LqrGains g = lqr_gains(*p_.dynamics, p_.nominal, p_.tau, s_.rk4_substeps, w);
    out_.gain_time += tg.seconds();
    return g;
  }

  VerifyOutcome verify(const LqrGains& g) {
    const Stopwatch tv;
    VerifyOutcome v = verify_funnel(p_, g.K, g.closed, vo_, g.cost);
    out_.verify_time += tv.seconds();
    ++out_.attempts;
    out_.stopped = out_.stopped || v.stopped;
    return v;
  }

  // The gains g through the passes (cheap first); true if some pass got further than best.
  // `last` receives the furthest pass of g (its input hulls feed the input-aware weights).
  // A pass that fails replaces best only when `ranked` (the ladder's): the input-aware rounds
  // are kept when they verify, and a miss is reported as the ladder's, whose reason (a centre
  // off the nominal, the share of saturated steps) the outer search reacts to.
  bool verify_gains(const LqrGains& g, VerifyOutcome& last, const std::vector<int>& passes, bool ranked) {
    bool further = false;
    last.reached_step = -1;
    for (const int order : passes) {
      vo_.reach_order = order;
      VerifyOutcome v = verify(g);
      if (out_.stopped) break;
      if (v.ok && order != orders_.back() && v.max_fill > kRoomyFill) {
        // Verified, but its sets use much of the tube: the tighter pass gives the monitor and
        // the tightness figure sets up to 2x smaller (funnel_bench); this one stays as the fallback.
        cheap_ = std::move(v);
        continue;
      }
      if (!v.ok && v.reached_step >= last.reached_step) last = v;
      if (v.ok || (ranked && v.reached_step > best().reached_step)) {
        best() = std::move(v);
        out_.order = order;
        further = true;
      }
      if (best().ok) break;
    }
    return further;
  }

  // Gains g missed with some input saturated: redesigned with R raised where the input hull left
  // U, up to input_rounds times, while each redesign gets further and still saturates.
  void input_aware_rounds(LqrGains g, VerifyOutcome& last, const LqrWeights& wt) {
    int reached = last.reached_step;
    for (int round = 0; round < s_.input_rounds && !best().ok && !cheap_.ok && !out_.stopped; ++round) {
      LqrWeights aware = wt;
      const InputReweighting rw = input_aware_weights(p_, g, last, aware.r_steps);
      if (rw.rows == 0) break;
      LqrGains h = design(aware);
      if (!h.ok()) break;
      ++out_.input_rounds;
      out_.reweighted_rows = rw.rows;
      verify_gains(h, last, {orders_.back()}, false);
      out_.input_reached = std::max(out_.input_reached, last.reached_step);
      if (best().ok) out_.input_aware = true;
      // A redesign that got no further, or left no input saturated by more than 1% of U, ends
      // the rounds: the miss is then the enclosure's, not the inputs' (on
      // tests/problems/15 the boat's later rounds missed with r past U by 0.003 or less).
      if (!saturation_matters(p_, last) || last.reached_step <= reached) break;
      reached = last.reached_step;
      g = std::move(h);
    }
  }

  // The gains that got furthest, verified again with splits, once.
  void verify_with_splits(int split_depth) {
    vo_.split_depth = split_depth;
    vo_.reach_order = orders_.back();  // the tighter pass: splits pay only where the rest is tight
    VerifyOutcome v = verify(furthest_);
    out_.split_tried = true;
    if (v.ok || v.reached_step > best().reached_step) {
      best() = std::move(v);
      out_.order = orders_.back();
    }
  }

  const Options& s_;
  const TrackingProblem& p_;
  VerifyOptions vo_;
  std::vector<int> orders_;  // the reach orders of the passes, the tighter last
  Search out_;
  VerifyOutcome cheap_;  // a cheap pass that verified with roomy sets: the fallback
  LqrGains furthest_;    // the ladder's gains that got furthest
};

FunnelTracker::Search FunnelTracker::search(const TrackingProblem& p, const std::function<bool()>& stop) const {
  return Ladder(*this, p, stop).run();
}

TrackResult FunnelTracker::track(const TrackingProblem& p, const TrackOptions& options) const {
  TrackResult res;
  if (!p.dynamics) {
    res.message = "no dynamics";
    return res;
  }
  const int n = p.dynamics->state_dim(), m = p.dynamics->input_dim();
  const int T = static_cast<int>(p.nominal.u.size());
  if (n + m > kMaxDual) {
    res.message = "the funnel tracker handles agents with states + inputs <= " + std::to_string(kMaxDual);
    return res;
  }
  if (T < 1 || static_cast<int>(p.nominal.x.size()) != T + 1 || p.tube.eps.size() != n || p.tube.w.size() != n ||
      p.input_bounds.dim() != m) {
    res.message = "inconsistent tracking problem (nominal length, eps, w or input bounds)";
    return res;
  }
  if (!s_.initial_radius.empty() && static_cast<int>(s_.initial_radius.size()) != n) {
    res.message = "initial_radius: expected " + std::to_string(n) + " numbers, got " + std::to_string(s_.initial_radius.size());
    return res;
  }
  if (p.initial_radius.size() != 0 && p.initial_radius.size() != n) {
    res.message = "the stated initial set has " + std::to_string(p.initial_radius.size()) + " half-widths, expected " + std::to_string(n);
    return res;
  }
  if (const int i = uncovered_coordinate(p.initial_radius); i >= 0) {
    res.message = "initial_radius " + number_text(s_.initial_radius[static_cast<std::size_t>(i)]) +
                  " does not hold the stated initial set (x0_radius " + number_text(p.initial_radius[i]) + ") in coordinate " +
                  std::to_string(i);
    return res;
  }
  Search found = search(p, options.stop);
  if (found.stopped && !found.best.ok) {  // a funnel verified before the stop (the cheap pass) stands
    res.status = TrackerStatus::ResourceLimit;
    res.message = "stopped by the run after " + number_text(found.gain_time + found.verify_time, 3) + " s, in verification " +
                  std::to_string(found.attempts);
    return res;
  }
  // The reachable tube, before the invariant sets widen the stored ones.
  if (found.best.ok) res.stats.tube_kept = tube_use(found.best.half_width, Eigen::VectorXd::Ones(n));
  if (s_.invariant_sets) make_invariant(p, verify_options(p.tube.eps, p.initial_radius), found.best);
  const VerifyOutcome& best = found.best;
  const int best_order = found.order, weight_choices = found.weight_choices;
  const double gain_time = found.gain_time, verify_time = found.verify_time;
  const int attempts = found.attempts;
  res.stats.abstraction_time_s = gain_time;
  res.stats.synthesis_time_s = verify_time;
  res.stats.boxes_computed = static_cast<long long>(attempts) * T * s_.substeps;
  res.stats.enclosure_substeps = s_.parts;
  // The funnel's own figure: the agent's initial set lies in the verified set of step 0.
  res.stats.set("initial_state_winning", "initial set in V_0", best.ok);
  if (!best.ok) {
    res.status = TrackerStatus::NoController;
    res.message = best.reached_step < 0 ? "the LQR recursion broke down (non-finite gains)"
                                        : "no verified funnel (" + std::to_string(weight_choices) + " weight choice(s)" +
                                              (found.input_rounds ? ", " + std::to_string(found.input_rounds) +
                                                                        " input-aware redesign(s), the furthest to step " +
                                                                        std::to_string(found.input_reached + 1)
                                                                  : std::string()) +
                                              (found.split_tried ? ", the furthest again with splits up to depth " +
                                                                       std::to_string(s_.split_depth)
                                                                 : std::string()) +
                                              "): " + best.why;
    res.failure = failure_of(best, p.tube.eps);
    return res;
  }
  if (reach_out_) *reach_out_ = best.reach;
  const FunnelData& d = best.data;
  res.stats.peak_memory_bytes = static_cast<long long>(8 * (d.horizon() + 1) * (3 * n + n * n + m * (n + 1)) +
                                                       d.enclosures.size() * sizeof(PeriodEnclosure));
  std::ostringstream msg;
  msg.precision(3);
  msg << "verified sets fill at most " << 100 * best.max_fill << "% of eps (mean " << 100 * best.mean_fill << "%)";
  msg << ", enclosure carried with " << best_order << " n generators";
  if (best.saturated_steps) msg << ", inputs saturate on " << best.saturated_steps << " step(s)";
  if (best.shifted_steps) msg << ", u_k moved inside U on " << best.shifted_steps << " step(s)";
  if (found.input_aware)
    msg << ", input-aware weights (redesign " << found.input_rounds << ", R raised on " << found.reweighted_rows
        << " (step, input) row(s) where the input hull left U)";
  if (best.splits)
    msg << ", " << best.splits << " split(s), up to " << best.max_parts << " parts carried (" << best.periods
        << " periods enclosed for " << T << " steps)";
  auto controller = std::make_shared<FunnelController>(best.data);
  if (s_.tightness_runs > 0) {
    const Tightness t = measure_tightness(*p.dynamics, *controller, best.half_width, static_cast<int>(s_.tightness_runs), 1);
    msg << "; tightness (verified half-width / largest deviation in " << t.runs << " adversarial runs): "
        << describe(t, p.dynamics->state_names());
  }
  msg << "; " << sets_text(d, best.invariant, s_.invariant_sets, p.dynamics->state_names());
  // From this step the controller's acceptance (and its exported monitor) means "safe from here".
  res.stats.set("invariant_from", "leading sets not invariant", static_cast<long long>(d.invariant_from));
  if (best.rows > 0) msg << "; second-order remainder on " << 100 * best.second_order_rows / best.rows << "% of rows";
  res.message = msg.str();
  res.controller = controller;
  res.status = TrackerStatus::ControllerFound;
  return res;
}

std::shared_ptr<const Controller> FunnelTracker::read_controller(const std::string& path) const {
  return funnel::read_controller(path);
}

}  // namespace marsyn::funnel
