#pragma once
// Eigen vectors and rows of vectors as numpy arrays, shared by the module's files.
#include <pybind11/numpy.h>

#include <cmath>
#include <vector>

#include <Eigen/Core>

namespace marsyn::python {

namespace py = pybind11;

// rows[r] as row r of a (rows, cols) array; NaN where a row is shorter than cols.
inline py::array_t<double> matrix(const std::vector<Eigen::VectorXd>& rows, int cols) {
  py::array_t<double> a({static_cast<py::ssize_t>(rows.size()), static_cast<py::ssize_t>(cols)});
  auto v = a.mutable_unchecked<2>();
  for (size_t r = 0; r < rows.size(); ++r)
    for (int c = 0; c < cols; ++c) v(static_cast<py::ssize_t>(r), c) = c < rows[r].size() ? rows[r][c] : NAN;
  return a;
}

inline py::array_t<double> vector(const Eigen::VectorXd& x) {
  py::array_t<double> a(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) a.mutable_at(i) = x[i];
  return a;
}

}  // namespace marsyn::python
