#include "input_pieces.hpp"

#include <algorithm>

namespace marsyn::altro::detail {

namespace {
std::vector<std::vector<int>> by_agent(const std::vector<InputPiece>& pieces, int agents) {
  std::vector<std::vector<int>> list(agents);
  for (size_t p = 0; p < pieces.size(); ++p) list[pieces[p].agent].push_back(static_cast<int>(p));
  return list;
}
}  // namespace

Eigen::SparseMatrix<double> gram_by_agent(const std::vector<InputPiece>& pieces, const std::vector<double>& values,
                                          const std::vector<int>& inputs_of_agent, int rows) {
  const int N = static_cast<int>(inputs_of_agent.size());
  const auto list = by_agent(pieces, N);
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < N; ++i) {
    const int m = inputs_of_agent[i];
    for (size_t x = 0; x < list[i].size(); ++x)
      for (size_t y = 0; y <= x; ++y) {
        const InputPiece &p = pieces[list[i][x]], &q = pieces[list[i][y]];
        const long len = static_cast<long>(std::min(p.last, q.last) + 1) * m;
        const double d = Eigen::Map<const Eigen::VectorXd>(values.data() + p.at, len)
                             .dot(Eigen::Map<const Eigen::VectorXd>(values.data() + q.at, len));
        entries.emplace_back(std::max(p.row, q.row), std::min(p.row, q.row), d);
      }
  }
  Eigen::SparseMatrix<double> M(rows, rows);
  M.setFromTriplets(entries.begin(), entries.end());  // duplicates (two shared agents) are summed
  return M;
}

double gram_work(const std::vector<InputPiece>& pieces, const std::vector<int>& inputs_of_agent, int steps) {
  std::vector<double> count(inputs_of_agent.size(), 0.0);
  for (const auto& p : pieces) count[p.agent] += 1.0;
  double work = 0.0;
  for (size_t i = 0; i < count.size(); ++i) work += count[i] * count[i] * steps * inputs_of_agent[i];
  return work;
}

void add_transpose_times(const std::vector<InputPiece>& pieces, const std::vector<double>& values,
                         const std::vector<int>& inputs_of_agent, const std::vector<int>& input_offset, int m,
                         const Eigen::VectorXd& y, Eigen::VectorXd& dU) {
  for (const auto& p : pieces) {
    const int ma = inputs_of_agent[p.agent];
    for (int j = 0; j <= p.last; ++j)
      dU.segment(static_cast<long>(j) * m + input_offset[p.agent], ma) +=
          y[p.row] * Eigen::Map<const Eigen::VectorXd>(values.data() + p.at + static_cast<long>(j) * ma, ma);
  }
}

}  // namespace marsyn::altro::detail
