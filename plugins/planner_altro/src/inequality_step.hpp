#pragma once
// The final projection's step for rows that are inequalities: the least-norm dU = J' y with
// c + J dU <= 0 to first order, where M = J J'. A satisfied row held at its value beside a nearly
// parallel violated one (a knot beside the interior point next to it) asks for opposite changes
// along almost the same gradient, and the least-norm step of the equations blows up; as
// inequalities the violated row carries the other along.
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace marsyn::altro::detail {

// M: J J' (lower triangle, as gram_by_agent returns it); c: the rows' values; damp: added to the
// diagonal of each solve. Active set: the violated rows first; a row whose multiplier comes out
// with the wrong sign (y_r > 0: it would be strictly satisfied without its equation) leaves, and,
// when none does, every row the step would break to first order (c + M y > 0) joins, driven to its
// bound; at most `rounds` solves. y: the last solve's (zero outside the set). False when no row is
// violated or a factorization fails.
bool inequality_step(const Eigen::SparseMatrix<double>& M, const Eigen::VectorXd& c, double damp, int rounds,
                     Eigen::VectorXd& y);

}  // namespace marsyn::altro::detail
