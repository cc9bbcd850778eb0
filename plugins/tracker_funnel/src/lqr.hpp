#pragma once
// Time-varying discrete-time LQR along a nominal trajectory: the feedback gains of the funnel
// controller. A_k, B_k are the exact Jacobians (forward-mode AD) of the RK4 sampled map at
// (x_k, u_k). The gains need no accuracy for soundness: the verification encloses the closed
// loop whatever K is; good gains only make the verified sets small.
#include <vector>

#include <Eigen/Core>

#include "marsyn/dynamics.hpp"
#include "marsyn/problem.hpp"

namespace marsyn::funnel {

struct LqrWeights {
  Eigen::VectorXd q;  // state weights (n), diagonal of Q
  Eigen::VectorXd r;  // input weights (m), diagonal of R
  // Per step k < T (may be empty): R_k's diagonal instead of r, the input-aware weights that
  // soften the feedback where its input hull leaves U (input_weights.hpp).
  std::vector<Eigen::VectorXd> r_steps;
  double terminal = 1.0;  // P_T = terminal Q
};

struct LqrGains {
  std::vector<Eigen::MatrixXd> K;       // K_0..K_{T-1} (m x n): u = u_k + K_k (x - x_k)
  std::vector<Eigen::MatrixXd> closed;  // A_k + B_k K_k, the closed loop's linearization
  std::vector<Eigen::MatrixXd> cost;    // P_k, the cost-to-go: the closed loop contracts in its norm
  std::vector<Eigen::VectorXd> bpb;     // diagonal of B_k' P_{k+1} B_k: how much R_k moves K_k
  std::vector<Eigen::VectorXd> r;       // R_k's diagonal as used
  bool ok() const { return !K.empty(); }
};

// Empty when the Riccati recursion breaks down (non-finite values).
LqrGains lqr_gains(const Dynamics& f, const NominalTrajectory& nominal, double tau,
                                       int rk4_substeps, const LqrWeights& weights);

}  // namespace marsyn::funnel
