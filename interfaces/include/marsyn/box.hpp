#pragma once
#include <Eigen/Core>

namespace marsyn {

// Axis-aligned box [lo, hi] (closed), in the coordinates of whatever space it lives in.
struct Box {
  Eigen::VectorXd lo, hi;

  int dim() const { return static_cast<int>(lo.size()); }
  bool empty() const { return (lo.array() > hi.array()).any(); }
  bool contains(const Eigen::VectorXd& x) const {
    return (x.array() >= lo.array()).all() && (x.array() <= hi.array()).all();
  }
  // Minkowski difference with the box [-r, r] (the paper's "shrunk by eps").
  Box shrunk(const Eigen::VectorXd& r) const { return {lo + r, hi - r}; }
  Box grown(const Eigen::VectorXd& r) const { return {lo - r, hi + r}; }
  Eigen::VectorXd center() const { return 0.5 * (lo + hi); }
};

}  // namespace marsyn
