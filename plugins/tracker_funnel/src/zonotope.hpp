#pragma once
// Zonotopes {c + G xi : |xi|_inf <= 1} with doubles for c and G, built soundly from interval
// data: every rounding error of a computation is moved into axis-aligned generators, so the
// stored (c, G) contains every point the exact real computation could produce. A zonotope
// carries a linear map without the wrapping effect of boxes (docs/soundness.md section 11).
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "marsyn/fast_interval.hpp"

namespace marsyn::funnel {

using IVector = std::vector<FastInterval>;

// Row-major interval matrix.
struct IMatrix {
  int rows = 0, cols = 0;
  std::vector<FastInterval> a;
  IMatrix() = default;
  IMatrix(int r, int c) : rows(r), cols(c), a(static_cast<std::size_t>(r) * c, FastInterval(0.0)) {}
  FastInterval& operator()(int i, int j) { return a[static_cast<std::size_t>(i) * cols + j]; }
  const FastInterval& operator()(int i, int j) const { return a[static_cast<std::size_t>(i) * cols + j]; }
};

struct Zonotope {
  Eigen::VectorXd c;
  Eigen::MatrixXd G;  // rows = dimension, one column per generator

  int dim() const { return static_cast<int>(c.size()); }
  int generators() const { return static_cast<int>(G.cols()); }
  // Upper bound of sum_j |G_ij|: the half-width of the interval hull along coordinate i.
  double radius(int i) const;
  // Sound interval hull of coordinate i.
  FastInterval hull(int i) const;
};

// Upper bound of max(hi - m, m - lo) for the midpoint m of x: x lies in m + [-r, r].
double radius_about(const FastInterval& x, double m);

// The zonotope {c + G xi + diag(extra) eta : c in center, G in gens, |xi|, |eta| <= 1} enclosed
// by a double one: midpoints are kept and the intervals' radii (and `extra`, upper bounds, may be
// empty) become one axis-aligned generator per coordinate.
Zonotope from_intervals(const IVector& center, const IMatrix& gens, const std::vector<double>& extra);

// The double zonotope of the midpoints of center and gens; radii[i] receives an upper bound of
// the distance along i between any realisation of the intervals and it (the caller keeps it as
// a box).
Zonotope midpoints(const IVector& center, const IMatrix& gens, std::vector<double>& radii);

// z with the box diag(b) appended (zero entries are skipped).
void append_box(Zonotope& z, const std::vector<double>& b);

// Girard's reduction: keeps the first `keep` generators (the propagated basis) and replaces the
// others with the smallest ||g||_1 - ||g||_inf by their box until at most `max_generators` remain.
// The box of the removed ones is an upper bound, so the result contains the input.
void reduce_order(Zonotope& z, int keep, int max_generators);

// Drops generators that are zero in every coordinate (exact, so sound).
void drop_zero_generators(Zonotope& z);

// The two halves of z along generator j: c +- g_j / 2 with g_j halved (xi_j in [0, 1] is
// 1/2 + eta / 2, eta in [-1, 1]), so their union is z. Halving is exact; the rounding of
// c +- g_j / 2 becomes a box (from_intervals), so each double half contains its exact one.
std::pair<Zonotope, Zonotope> split(const Zonotope& z, int j);

}  // namespace marsyn::funnel
