#pragma once
// Verified sets that are invariant, not only reached (docs/soundness.md section 11, "Invariant
// sets"): after the forward verification, from the last step back to the first, each stored
// parallelotope V_k is scaled up (toward its box inside the eps-tube) as far as one period of the
// closed loop from every state it accepts, under every disturbance in W, still ends in V_{k+1}.
// Then a state the controller accepts at step k has the guarantee from there on, whether or not a
// run from the initial set reaches it: the monitor's 1 means "safe from here".
#include <vector>

#include "funnel_controller.hpp"
#include "marsyn/tracker.hpp"
#include "period_law.hpp"

namespace marsyn::funnel {
struct VerifyOptions;
}

namespace marsyn::funnel {

// The highest order (generators per state) of a zonotope chain: the chain carries what it stores,
// so a low order boxes generators at every step (on the examples' quadrotors orders 2 and 4 do
// not hold over 50 steps, 8 does); a higher one costs the controller's membership test and table
// size in proportion (docs/funnel.md, "Invariant sets"). Order 4 is not tried: it held nowhere 2
// did not, and a chain that fails late costs a whole pass.
inline constexpr int kChainOrder = 8;

struct InvariantOutcome {
  // V_k is invariant for every k >= from_step (each accepted state's successors are accepted at
  // k + 1, and the period enclosures of step k cover every run from V_k); horizon + 1: none.
  int from_step = 0;
  int grown = 0;           // steps whose set was scaled beyond the forward verification's
  double mean_scale = 1.0;  // over the invariant steps k >= 1: the factor V_k was scaled by
  long periods = 0;        // periods enclosed by this pass
  double floor = 0.0;       // the chain's sets widened to at least this fraction of eps (where the box allows)
  int order = -1;          // a chain from V_0: 0 parallelotopes, else zonotopes of order n generators; -1: none
};

// The sets V_0 ... V_T of d (the forward verification's, each containing its reachable set) and
// the period enclosures are updated in place; `parts` period enclosures per step, `spp` substeps
// each. A step whose set is not a parallelotope, or where no candidate holding the reachable set
// maps into V_{k+1}, ends the invariant suffix: the steps before it keep the forward sets and enclosures,
// whose guarantee is from the initial set only.
// reach: per step, the parts of the reachable-set enclosure the verification carried (V_k must
// keep holding them); where it is empty the forward V_k is what must be held.
// o: the verification's options (the fit of a set around a period's end).
InvariantOutcome grow_invariant_sets(const TrackingProblem& p, const PeriodLaw& law, FunnelData& d, int parts, int spp,
                                     const std::vector<std::vector<Zonotope>>& reach, const VerifyOptions& o);

// The states a parallelotope test {x in [lo, hi] : |fl(S (x - c))|_inf <= 1} can accept (the real
// state, the controller reading its nearest double), as a zonotope c + S^-1 diag(r) xi plus a box:
// r_i = 1 + the test's rounding and measurement allowance, S^-1 a verified inverse (its error in
// the box). False when S is too ill-conditioned to bound the inverse.
bool parallelotope_zonotope(const StepSet& s, int n, Zonotope& out);
// The same for any stored set: a zonotope set's accepted states (residual tolerance, the test's
// rounding and the measurement allowed for), or a parallelotope's as above.
bool accepted_zonotope(const StepSet& s, int n, Zonotope& out);

// Row i of a parallelotope test: an upper bound of |S_i (x - c)| over the parts plus the
// rounding and measurement allowance of the run-time test; the parts are in the set along row i
// when it is at most 1.
double parallelotope_row_need(const StepSet& s, int i, const std::vector<Zonotope>& parts, int n);
// That allowance alone: kappa sum_j |S_ij| max |x_j - c_j| over the box, plus the measured
// state's distance to the real one.
double parallelotope_slack(const StepSet& s, int i, int n, double kappa);

// Whether every state of the parts lies in the stored set s (its box, and for a parallelotope
// |fl(S (x - c))|_inf <= 1 with the run-time test's rounding and measurement allowed for), in
// interval arithmetic. A zonotope set is never claimed (no containment test for it here).
bool contains(const StepSet& s, const std::vector<Zonotope>& parts, int n);

}  // namespace marsyn::funnel
