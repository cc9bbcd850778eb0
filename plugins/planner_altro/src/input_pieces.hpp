#pragma once
// The final projection's Jacobian in the inputs, stored sparsely: a row reads one or two agents,
// and through the dynamics only their inputs up to its step, so each row keeps per agent one
// piece, its gradient in that agent's inputs of steps 0..last.
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace marsyn::altro::detail {

struct InputPiece {
  int row, agent, last;
  long at;  // values[at ..]: (last + 1) x m of the agent, step-major
};

// J J' (lower triangle), summed agent by agent over the pieces sharing it: the work is
// sum_a rows_a^2 x T x m_a instead of rows^2 x T x m for the dense product.
Eigen::SparseMatrix<double> gram_by_agent(const std::vector<InputPiece>& pieces, const std::vector<double>& values,
                                          const std::vector<int>& inputs_of_agent, int rows);

// The work gram_by_agent does: sum over agents of (pieces reading it)^2 x steps x its inputs.
double gram_work(const std::vector<InputPiece>& pieces, const std::vector<int>& inputs_of_agent, int steps);

// J' y into the product inputs dU (step-major, m per step; input_offset: each agent's first input).
void add_transpose_times(const std::vector<InputPiece>& pieces, const std::vector<double>& values,
                         const std::vector<int>& inputs_of_agent, const std::vector<int>& input_offset, int m,
                         const Eigen::VectorXd& y, Eigen::VectorXd& dU);

}  // namespace marsyn::altro::detail
