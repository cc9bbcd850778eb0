#include "lqr.hpp"

#include <Eigen/Cholesky>

#include "marsyn/sampled_map.hpp"

namespace marsyn::funnel {

LqrGains lqr_gains(const Dynamics& f, const NominalTrajectory& nominal, double tau,
                                       int rk4_substeps, const LqrWeights& wt) {
  const int n = f.state_dim(), m = f.input_dim();
  const int T = static_cast<int>(nominal.u.size());
  LqrGains g;
  std::vector<Eigen::MatrixXd> K(static_cast<std::size_t>(T)), closed(static_cast<std::size_t>(T)),
      cost(static_cast<std::size_t>(T) + 1);
  std::vector<Eigen::VectorXd> bpb(static_cast<std::size_t>(T)), rs(static_cast<std::size_t>(T));
  const Eigen::MatrixXd Q = wt.q.asDiagonal();
  Eigen::MatrixXd R(m, m);
  Eigen::MatrixXd P = wt.terminal * Q;
  cost[T] = P;
  Eigen::MatrixXd A(n, n), B(n, m);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> Ar(n, n), Br(n, m);
  for (int k = T - 1; k >= 0; --k) {
    rk4_jacobians(f, nominal.x[k].data(), nominal.u[k].data(), tau, rk4_substeps, nullptr, Ar.data(), Br.data());
    A = Ar;
    B = Br;
    rs[k] = static_cast<int>(wt.r_steps.size()) == T ? wt.r_steps[k] : wt.r;
    R = rs[k].asDiagonal();
    const Eigen::MatrixXd BPB = B.transpose() * P * B;
    bpb[k] = BPB.diagonal();
    const Eigen::MatrixXd S = R + BPB;
    const Eigen::MatrixXd Kk = -S.ldlt().solve(B.transpose() * P * A);
    if (!Kk.allFinite()) return {};
    K[k] = Kk;
    closed[k] = A + B * Kk;
    P = Q + A.transpose() * P * (A + B * Kk);
    P = 0.5 * (P + P.transpose()).eval();
    if (!P.allFinite()) return {};
    cost[k] = P;
  }
  g.K = std::move(K);
  g.closed = std::move(closed);
  g.cost = std::move(cost);
  g.bpb = std::move(bpb);
  g.r = std::move(rs);
  return g;
}

}  // namespace marsyn::funnel
