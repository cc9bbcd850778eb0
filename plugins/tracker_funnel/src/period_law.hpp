#pragma once
// One period of the closed loop u = sat_U(u_k + K_k (x - x_k)) from a zonotope of states: the
// law's rows become generators of the (x, u) zonotope (affine in the state, rounding allowed
// for), a row that leaves U is saturated or has its u_k moved inside U, and the flow is enclosed
// (period_flow.hpp). docs/soundness.md section 11, "Inputs over V_k" and "u_k moved inside U".
#include <vector>

#include <Eigen/Core>

#include "funnel_controller.hpp"
#include "marsyn/tracker.hpp"
#include "period_flow.hpp"

namespace marsyn::funnel {

struct Period {
  FlowResult fr;
  bool saturated = false;  // some row enclosed as sat_U of its hull (a box)
  bool shifted = false;    // some row's u_k moved inside U instead
  std::vector<double> u;   // the law's u_k as the controller will store it
};

class PeriodLaw {
 public:
  // d: the funnel's data so far (U, W and the boxes of the steps already verified); it must
  // outlive this object.
  PeriodLaw(const TrackingProblem& p, const std::vector<Eigen::MatrixXd>& K, const FunnelData& d, const FlowOptions& flow,
            bool shift_inputs);
  // The period of step k from zx (states inside d.sets[k]'s box): with saturated rows as boxes,
  // or, when some row saturates and shifting is allowed, the shifted law if its end reaches less
  // far out of the tube.
  Period best(const Zonotope& zx, int k) const;

 private:
  Period period(const Zonotope& zx, int k, bool shift) const;
  // How far the period's end reaches from x_{k+1} relative to eps (centre offset + radius), the
  // score that decides between saturating and shifting: a shift pays with the offset.
  double end_reach(const FlowResult& fr, int k1) const;

  const TrackingProblem& p_;
  const std::vector<Eigen::MatrixXd>& K_;
  const FunnelData& d_;
  FlowOptions flow_;
  bool shift_inputs_;
  double kappa_;
};

}  // namespace marsyn::funnel
