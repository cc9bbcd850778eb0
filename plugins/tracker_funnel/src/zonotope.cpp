#include "zonotope.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace marsyn::funnel {

using fast_detail::add_up;
using fast_detail::sub_up;

double Zonotope::radius(int i) const {
  double r = 0.0;
  for (Eigen::Index j = 0; j < G.cols(); ++j) r = add_up(r, std::fabs(G(i, j)));
  return r;
}

FastInterval Zonotope::hull(int i) const {
  const double r = radius(i);
  return FastInterval(c[i]) + FastInterval(-r, r);
}

double radius_about(const FastInterval& x, double m) {
  return std::max(sub_up(x.upper(), m), sub_up(m, x.lower()));
}

Zonotope from_intervals(const IVector& center, const IMatrix& gens, const std::vector<double>& extra) {
  const int n = static_cast<int>(center.size());
  Zonotope z;
  z.c.resize(n);
  std::vector<double> box(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    z.c[i] = median(center[i]);
    box[i] = radius_about(center[i], z.c[i]);
    if (!extra.empty()) box[i] = add_up(box[i], extra[i]);
  }
  const int p = gens.cols;
  z.G.setZero(n, p + n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < p; ++j) {
      const FastInterval& g = gens(i, j);
      const double m = median(g);
      z.G(i, j) = m;
      // xi_j in [-1, 1]: (g - m) xi_j lies in [-r, r].
      box[i] = add_up(box[i], radius_about(g, m));
    }
  for (int i = 0; i < n; ++i) z.G(i, p + i) = box[i];
  drop_zero_generators(z);
  return z;
}

Zonotope midpoints(const IVector& center, const IMatrix& gens, std::vector<double>& radii) {
  const int n = static_cast<int>(center.size()), p = gens.cols;
  Zonotope z;
  z.c.resize(n);
  z.G.resize(n, p);
  radii.assign(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    z.c[i] = median(center[i]);
    radii[i] = radius_about(center[i], z.c[i]);
    for (int j = 0; j < p; ++j) {
      const double m = median(gens(i, j));
      z.G(i, j) = m;
      radii[i] = add_up(radii[i], radius_about(gens(i, j), m));
    }
  }
  return z;
}

void append_box(Zonotope& z, const std::vector<double>& b) {
  const int n = z.dim();
  int extra = 0;
  for (int i = 0; i < n; ++i) extra += b[i] != 0.0;
  if (extra == 0) return;
  const Eigen::Index p = z.G.cols();
  z.G.conservativeResize(n, p + extra);
  z.G.rightCols(extra).setZero();
  int col = 0;
  for (int i = 0; i < n; ++i)
    if (b[i] != 0.0) z.G(i, p + col++) = b[i];
}

void drop_zero_generators(Zonotope& z) {
  std::vector<Eigen::Index> keep;
  for (Eigen::Index j = 0; j < z.G.cols(); ++j)
    if ((z.G.col(j).array() != 0.0).any()) keep.push_back(j);
  if (static_cast<Eigen::Index>(keep.size()) == z.G.cols()) return;
  Eigen::MatrixXd G(z.G.rows(), static_cast<Eigen::Index>(keep.size()));
  for (std::size_t k = 0; k < keep.size(); ++k) G.col(static_cast<Eigen::Index>(k)) = z.G.col(keep[k]);
  z.G = std::move(G);
}

void reduce_order(Zonotope& z, int keep, int max_generators) {
  const int n = z.dim(), p = z.generators();
  if (p <= max_generators) return;
  keep = std::clamp(keep, 0, p);
  // Each removed generator costs its box: n new generators replace those removed, so remove
  // enough to land at max_generators including the box.
  const int removable = p - keep;
  const int remove = std::min(removable, p - max_generators + n);
  if (remove <= 0) return;
  std::vector<int> order(static_cast<std::size_t>(removable));
  std::iota(order.begin(), order.end(), keep);
  std::vector<double> score(static_cast<std::size_t>(p), 0.0);
  for (int j = keep; j < p; ++j) score[j] = z.G.col(j).lpNorm<1>() - z.G.col(j).lpNorm<Eigen::Infinity>();
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return score[a] < score[b]; });
  std::vector<char> removed(static_cast<std::size_t>(p), 0);
  for (int k = 0; k < remove; ++k) removed[order[k]] = 1;
  std::vector<double> box(static_cast<std::size_t>(n), 0.0);
  for (int j = 0; j < p; ++j)
    if (removed[j])
      for (int i = 0; i < n; ++i) box[i] = add_up(box[i], std::fabs(z.G(i, j)));
  Eigen::MatrixXd G(n, p - remove + n);
  int col = 0;
  for (int j = 0; j < p; ++j)
    if (!removed[j]) G.col(col++) = z.G.col(j);
  G.rightCols(n).setZero();
  for (int i = 0; i < n; ++i) G(i, col + i) = box[i];
  z.G = std::move(G);
  drop_zero_generators(z);
}

std::pair<Zonotope, Zonotope> split(const Zonotope& z, int j) {
  const int n = z.dim(), p = z.generators();
  IMatrix gens(n, p);
  for (int i = 0; i < n; ++i)
    for (int l = 0; l < p; ++l) gens(i, l) = l == j ? FastInterval(z.G(i, l)) * FastInterval(0.5) : FastInterval(z.G(i, l));
  IVector lo(n), hi(n);
  for (int i = 0; i < n; ++i) {
    const FastInterval half = FastInterval(z.G(i, j)) * FastInterval(0.5);
    lo[i] = FastInterval(z.c[i]) - half;
    hi[i] = FastInterval(z.c[i]) + half;
  }
  return {from_intervals(lo, gens, {}), from_intervals(hi, gens, {})};
}

}  // namespace marsyn::funnel
