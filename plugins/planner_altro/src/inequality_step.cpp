#include "inequality_step.hpp"

#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

namespace marsyn::altro::detail {

namespace {
// Up to this many rows the solves are dense: one extraction per round, no symbolic analysis.
constexpr long kDenseRows = 600;
}  // namespace

bool inequality_step(const Eigen::SparseMatrix<double>& M, const Eigen::VectorXd& c, double damp, int rounds,
                     Eigen::VectorXd& y) {
  const long R = c.size();
  std::vector<char> in(static_cast<size_t>(R));
  bool any = false;
  for (long r = 0; r < R; ++r) any |= (in[r] = c[r] > 0);
  y = Eigen::VectorXd::Zero(R);
  if (!any) return false;
  Eigen::MatrixXd dense;
  if (R <= kDenseRows) {
    dense = Eigen::MatrixXd(M);
    dense.triangularView<Eigen::StrictlyUpper>() = dense.transpose();
  }
  std::vector<long> index(static_cast<size_t>(R)), set;
  for (int round = 0; round < rounds; ++round) {
    set.clear();
    for (long r = 0; r < R; ++r) {
      index[r] = in[r] ? static_cast<long>(set.size()) : -1;
      if (in[r]) set.push_back(r);
    }
    const long S = static_cast<long>(set.size());
    if (S == 0) return false;
    Eigen::VectorXd t(S), yS;
    for (long i = 0; i < S; ++i) t[i] = -c[set[i]];
    if (R <= kDenseRows) {
      Eigen::MatrixXd MS = dense(set, set);
      MS.diagonal().array() += damp;
      Eigen::LDLT<Eigen::MatrixXd> ldlt(MS);
      if (ldlt.info() != Eigen::Success) return false;
      yS = ldlt.solve(t);
    } else {
      std::vector<Eigen::Triplet<double>> entries;
      for (int col = 0; col < M.outerSize(); ++col) {
        if (index[col] < 0) continue;
        for (Eigen::SparseMatrix<double>::InnerIterator it(M, col); it; ++it)
          if (index[it.row()] >= 0) entries.emplace_back(index[it.row()], index[col], it.value());
      }
      for (long i = 0; i < S; ++i) entries.emplace_back(i, i, damp);
      Eigen::SparseMatrix<double> MS(S, S);
      MS.setFromTriplets(entries.begin(), entries.end());
      Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt(MS);
      if (ldlt.info() != Eigen::Success) return false;
      yS = ldlt.solve(t);
    }
    if (!yS.allFinite()) return false;
    y.setZero();
    for (long i = 0; i < S; ++i) y[set[i]] = yS[i];
    bool changed = false;
    for (long i = 0; i < S; ++i)
      if (yS[i] > 0) in[set[i]] = 0, changed = true;
    if (!changed) {
      const Eigen::VectorXd change = R <= kDenseRows ? Eigen::VectorXd(dense * y)
                                                      : Eigen::VectorXd(M.selfadjointView<Eigen::Lower>() * y);
      for (long r = 0; r < R; ++r)
        if (!in[r] && c[r] + change[r] > 0) in[r] = 1, changed = true;
    }
    if (!changed) break;
  }
  return true;
}

}  // namespace marsyn::altro::detail
