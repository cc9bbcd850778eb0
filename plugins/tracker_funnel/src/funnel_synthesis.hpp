#pragma once
// Verification of a funnel controller: from the initial box, period by period, a sound enclosure
// of the closed loop u = sat_U(u_k + K_k (x - x_k)) under every disturbance in [-W, W], the check
// that it stays in the eps-box of the next nominal state, and the fit of the verified set V_{k+1}
// the controller will accept (docs/soundness.md section 11).
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "funnel_controller.hpp"
#include "marsyn/tracker.hpp"
#include "invariant_sets.hpp"
#include "period_flow.hpp"

namespace marsyn::funnel {

struct VerifyOptions {
  FlowOptions flow;     // flow.tau is set from the problem
  int parts = 8;        // period enclosures per step (divides flow.substeps)
  int reach_order = 24;         // generators per state of the carried reachable-set enclosure
  bool zonotope_sets = false;   // store zonotopes of order set_order first (else parallelotopes)
  int set_order = 8;
  bool keep_reach = false;      // keep the reachable-set enclosures in the outcome (tests)
  // Where a row of u_k + K_k (x - x_k) leaves U over the set but is narrower than U: also try
  // the law with u_k moved inside U (no saturation, an offset), and keep whichever period ends
  // closer inside the tube.
  bool shift_inputs = true;
  // A part of the carried set whose period leaves the tube (or whose flow has no enclosure) is
  // split in two along its widest generator and each half verified under the same law, at most
  // split_depth times along any line of splits (at most 2^split_depth parts); 0: never.
  int split_depth = 3;
  // When splitting at the miss does not get the parts inside, every part of the set carried into
  // the step split_lookback steps before it is split (at most split_depth times in a run), and
  // the verification resumes there: the parts' smaller remainders add up over those periods.
  int split_lookback = 8;
  // Splitting stops (the next miss fails) once split_work T periods are enclosed in the run (a
  // run without splits encloses T): a failing agent pays at most that many passes' worth.
  int split_work = 8;
  Eigen::VectorXd initial_radius;  // half-widths of the initial box around x_0
  // The run's stop request (TrackOptions::stop), polled before each step: true ends the
  // verification unfinished (VerifyOutcome::stopped). May be empty.
  std::function<bool()> stop;
};

struct VerifyOutcome {
  bool ok = false;
  FunnelData data;
  std::string why;        // when !ok: the step, coordinate and amount that failed
  int reached_step = 0;   // steps verified before the failure
  bool stopped = false;   // ended by VerifyOptions::stop, not by the funnel
  int miss_coordinate = -1;  // when the enclosure left the tube: the coordinate and by how much
  double miss_amount = 0.0;
  bool miss_off_centre = false;  // the enclosure's centre is further from x_{k+1} than its half-width
  int saturated_steps = 0;  // steps where some input row hit U and was enclosed as a box
  int shifted_steps = 0;    // steps whose law's u_k was moved inside U instead
  double max_fill = 0.0;  // max over k, i of (hull half-width of V_k along i) / eps_i
  double mean_fill = 0.0;
  // Per step k = 0..T and coordinate i: max |x_i - x_k,i| over the hull of V_k (the tightness
  // figure's verified side, tightness.hpp).
  std::vector<std::vector<double>> half_width;
  long rows = 0, second_order_rows = 0;  // of the chosen periods' enclosures (FlowResult)
  int splits = 0;     // parts split in two (split_depth)
  int max_parts = 1;  // the most parts carried at once
  long periods = 0;   // periods enclosed, parts and verifications again from an earlier step included
  // Per step k, up to the one that failed, and input i: the law's row over the carried set with
  // the nominal's u_k (every part's hull), and whether some part's row was enclosed as a
  // saturated box; what the input-aware weights (input_weights.hpp) and a miss's report read.
  std::vector<std::vector<FastInterval>> input_hull;
  std::vector<std::vector<char>> input_boxed;
  // With keep_reach: per step k, parts whose union contains every state the closed loop reaches
  // at sample k from the initial box (V_k contains each).
  std::vector<std::vector<Zonotope>> reach;
  InvariantOutcome invariant;  // after make_invariant: from which step the sets are invariant
};

// K: the gains; closed (may be empty): the closed loop's linearization per step, whose real
// eigenbasis is one of the shapes tried for the verified sets.
VerifyOutcome verify_funnel(const TrackingProblem& p, const std::vector<Eigen::MatrixXd>& K,
                            const std::vector<Eigen::MatrixXd>& closed, const VerifyOptions& o,
                            const std::vector<Eigen::MatrixXd>& cost = {});

// Between the samples of step k: the a priori boxes of the periods in frs (the parts of a split
// set), hulled per part of the period, with their workspace footprint, appended to out.
void append_period_enclosures(const std::vector<const FlowResult*>& frs, const TrackingProblem& p, int k, int parts, int spp,
                              std::vector<PeriodEnclosure>& out);

// A verified outcome's sets grown backward into invariant ones (invariant_sets.hpp), its period
// enclosures with them; v.data.invariant_from and v.invariant say from which step. Without it
// each V_k only contains the states reached from the initial box.
void make_invariant(const TrackingProblem& p, const VerifyOptions& o, VerifyOutcome& v);

// set (its box lo, hi given) made the parallelotope of least volume, among the verification's
// candidate shapes (closed: the closed loop's linearization; basis: one more shape, its columns
// the parallelotope's axes; either may be null), that contains every part; false when none does.
bool fit_parallelotope(const std::vector<Zonotope>& parts, StepSet& set, const Eigen::MatrixXd* closed, const Eigen::MatrixXd* basis,
                       const VerifyOptions& o);

// set (its box given) made the zonotope z reduced to order generators per state (at most the
// membership test's 64), with the stored margin and tolerance; false when that is not possible.
bool fit_zonotope(const Zonotope& z, int order, StepSet& set);

// The enclosure options of a verification: o.flow with the problem's period and the carried
// set's generator budget.
FlowOptions flow_options(const TrackingProblem& p, const VerifyOptions& o);

// The rounding allowance for sums of `terms` products evaluated left to right in double
// (Higham's gamma_n with room for the subtraction in each term): |fl(s) - s| <= kappa * sum |terms|.
double rounding_factor(int terms);

}  // namespace marsyn::funnel
