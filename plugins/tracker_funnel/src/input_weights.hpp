#pragma once
// Input-aware LQR weights (issue 23, item 4): where a verification found the law's input hull
// u_k + K_k (x - x_k) over the carried set leaving U, the input weight R_k of that channel and
// step is raised so that the redesigned gain's row, scaled down, would fit inside U over the same
// set. A row inside U stays affine in the state (correlated); a saturated row becomes a box.
// The gains never enter the soundness argument (docs/soundness.md section 11): any K is verified
// as it is, saturation included, so these weights only decide what has a chance to verify.
#include <vector>

#include <Eigen/Core>

#include "funnel_synthesis.hpp"
#include "lqr.hpp"

namespace marsyn::funnel {

struct InputReweighting {
  int rows = 0;           // (step, input) rows whose R was raised
  int first_step = -1;    // the first and last step with one
  int last_step = -1;
};

// Whether some row of v that was enclosed as a saturated box left U by more than `share` of U's
// width: below that, the box is about as narrow as the affine row, and a miss is the enclosure's.
bool saturation_matters(const TrackingProblem& p, const VerifyOutcome& v, double share = 0.01);

// From the gains g (their R_k and B_k' P_{k+1} B_k) and the verification v of g (its per-step
// input hulls, with the nominal's u_k, over the carried set): for every step k it reached and
// every input i whose hull leaves U, the gain scale a in [floor, 1) under which the row's hull,
// scaled about u_k, fits inside U (a margin of `margin` of the way to the bound), and
// R_k,ii = (R_k,ii + b_ii) / a - b_ii, which scales the row of K_k by about a for this P_{k+1}.
// r_steps receives the new weights (R_k of g elsewhere).
InputReweighting input_aware_weights(const TrackingProblem& p, const LqrGains& g, const VerifyOutcome& v,
                                     std::vector<Eigen::VectorXd>& r_steps, double floor = 0.05, double margin = 0.9);

}  // namespace marsyn::funnel
