#include <gtest/gtest.h>

#include <random>

#include <Eigen/Dense>

#include "src/input_pieces.hpp"

using namespace marsyn::altro::detail;

// The projection's J J' and J' y from the pieces equal the dense products of the same J.
TEST(InputPieces, GramAndTransposeEqualTheDenseProducts) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> val(-1.0, 1.0);
  const int T = 9, N = 4, rows = 12;
  const std::vector<int> m_of = {2, 1, 2, 3}, offset = {0, 2, 3, 5};
  const int m = 8;
  std::vector<InputPiece> pieces;
  std::vector<double> values;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(rows, T * m);
  for (int r = 0; r < rows; ++r)
    for (int a : {r % N, (r * 3 + 1) % N}) {  // one or two agents per row
      if (!pieces.empty() && pieces.back().row == r && pieces.back().agent == a) continue;
      const int last = static_cast<int>(gen() % T);
      pieces.push_back({r, a, last, static_cast<long>(values.size())});
      for (int j = 0; j <= last; ++j)
        for (int c = 0; c < m_of[a]; ++c) {
          values.push_back(val(gen));
          J(r, j * m + offset[a] + c) = values.back();
        }
    }
  const Eigen::MatrixXd dense = J * J.transpose();
  const Eigen::MatrixXd M = Eigen::MatrixXd(gram_by_agent(pieces, values, m_of, rows));
  for (int r = 0; r < rows; ++r)
    for (int s = 0; s <= r; ++s) EXPECT_NEAR(M(r, s), dense(r, s), 1e-12) << r << " " << s;
  Eigen::VectorXd y(rows);
  for (int r = 0; r < rows; ++r) y[r] = val(gen);
  Eigen::VectorXd dU = Eigen::VectorXd::Zero(T * m);
  add_transpose_times(pieces, values, m_of, offset, m, y, dU);
  EXPECT_LT((dU - J.transpose() * y).norm(), 1e-12);
  EXPECT_GT(gram_work(pieces, m_of, T), 0.0);
}
