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
  // Per input: the row's hull over the start with the nominal's u_k (feedback, rounding and
  // measurement included), whether or not it was moved, and whether the row was enclosed as a
  // saturated box; what the input-aware weights and a miss's report read.
  std::vector<FastInterval> nominal_hull;
  std::vector<char> boxed;
};

class PeriodLaw {
 public:
  // d: the funnel's data so far (U, W and the boxes of the steps already verified); it must
  // outlive this object.
  PeriodLaw(const TrackingProblem& p, const std::vector<Eigen::MatrixXd>& K, const FunnelData& d, const FlowOptions& flow,
            bool shift_inputs);
  // The periods of step k from the parts of the carried set (states inside d.sets[k]'s box),
  // one law for all (the controller stores one u_k): with saturated rows as boxes, or, when
  // some row saturates and shifting is allowed, the law with u_k moved inside U over every
  // part, if the parts' ends reach less far out of the tube.
  std::vector<Period> best(const std::vector<const Zonotope*>& parts, int k) const;
  Period best(const Zonotope& zx, int k) const { return std::move(best({&zx}, k).front()); }
  // The period of step k from zx under the law with u_k = u (a part split off a set whose
  // law is chosen already).
  Period with_input(const Zonotope& zx, int k, const std::vector<double>& u) const;

 private:
  // The law's rows over zx: the feedback K_k (x - x_k) with its generators and allowances.
  struct Rows {
    IVector center;
    IMatrix gens;
    std::vector<FastInterval> fb;
    std::vector<double> round, meas, spread;
  };
  Rows rows(const Zonotope& zx, int k) const;
  // Row i's hull for the law's input ui, with its centre and rounding allowance.
  FastInterval row_hull(const Rows& r, int i, double ui, FastInterval& c, double& delta) const;
  // The period with u_k = u: rows inside U stay affine, the others are saturated boxes.
  Period enclose(Rows r, int k, const std::vector<double>& u) const;
  // u_k moved, row by row, by the least amount that keeps the row's hull inside U over every
  // part (rows whose hull is wider than U, or need no move, keep theirs); moved says if any did.
  std::vector<double> shifted(const std::vector<Rows>& rows, int k, bool& moved) const;
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
