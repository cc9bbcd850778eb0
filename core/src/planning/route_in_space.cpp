// Routes in a 3-D workspace (routes.hpp): a lattice search over the prisms' bounding planes,
// then the lattice path shortened by visibility.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <queue>

#include "marsyn/core/planning/geometry.hpp"
#include "marsyn/core/planning/routes.hpp"

namespace marsyn::planning {

namespace {

// Where the segment a-b enters the prism's interior, as a fraction of the way (Cyrus-Beck
// against the side faces' and the caps' inner half-spaces); infinity when it does not: touching
// a face, an edge or a vertex is not crossing.
double entry(const Prism& prism, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  constexpr double kNever = std::numeric_limits<double>::infinity();
  const Eigen::Vector3d d = b - a;
  double t0 = 0.0, t1 = 1.0;
  // Inside the half-space of outward normal `out` through a point at offset `num` = out . (v - a):
  // t den < num with den = out . d.
  auto clip = [&](double num, double den) {
    if (den == 0.0) return num > 0.0;  // parallel: inside all along or out all along
    if (den > 0.0)
      t1 = std::min(t1, num / den);
    else
      t0 = std::max(t0, num / den);
    return t0 < t1;
  };
  if (std::isfinite(prism.z_hi) && !clip(prism.z_hi - a.z(), d.z())) return kNever;
  if (std::isfinite(prism.z_lo) && !clip(a.z() - prism.z_lo, -d.z())) return kNever;
  const auto& poly = prism.base;
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d e = poly[(i + 1) % n] - poly[i];
    const Eigen::Vector2d out(e.y(), -e.x());
    const double num = out.dot(poly[i] - a.head<2>()), den = out.dot(d.head<2>());
    if (!clip(num, den)) return kNever;
  }
  return t1 - t0 > 1e-9 * (1.0 + d.norm()) ? t0 : kNever;
}

bool crosses(const Prism& prism, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return entry(prism, a, b) < std::numeric_limits<double>::infinity();
}

bool strictly_inside(const Prism& prism, const Eigen::Vector3d& p) {
  const double tz = 1e-12 * (1.0 + std::abs(p.z()));
  if (!(p.z() > prism.z_lo + tz && p.z() < prism.z_hi - tz)) return false;
  const auto& poly = prism.base;
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d e = poly[(i + 1) % n] - poly[i];
    if (Eigen::Vector2d(e.y(), -e.x()).dot(p.head<2>() - poly[i]) >= -1e-12 * (1.0 + e.norm())) return false;
  }
  return n >= 3;
}

struct Bounds {
  Eigen::Vector3d lo, hi;
};

class Scene {
 public:
  explicit Scene(const std::vector<Prism>& prisms) : prisms_(prisms) {
    for (const auto& p : prisms) {
      Bounds b{Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()),
               Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity())};
      for (const auto& v : p.base)
        for (int c = 0; c < 2; ++c) b.lo[c] = std::min(b.lo[c], v[c]), b.hi[c] = std::max(b.hi[c], v[c]);
      b.lo.z() = p.z_lo;
      b.hi.z() = p.z_hi;
      boxes_.push_back(b);
    }
  }
  const Bounds& box(size_t i) const { return boxes_[i]; }

  bool free(const Eigen::Vector3d& p) const {
    return std::none_of(prisms_.begin(), prisms_.end(), [&](const Prism& q) { return strictly_inside(q, p); });
  }
  bool visible(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
    const Eigen::Vector3d lo = a.cwiseMin(b), hi = a.cwiseMax(b);
    for (size_t i = 0; i < prisms_.size(); ++i) {
      // Bounding boxes that do not overlap with volume: no crossing of the interior.
      if ((lo.array() >= boxes_[i].hi.array()).any() || (hi.array() <= boxes_[i].lo.array()).any()) continue;
      if (crosses(prisms_[i], a, b)) return false;
    }
    return true;
  }

 private:
  const std::vector<Prism>& prisms_;
  std::vector<Bounds> boxes_;
};

// The lattice planes on one axis: the box's ends, the route's ends, every prism's bounding planes
// inside the box, then every interval longer than `step` split evenly.
std::vector<double> planes(std::vector<double> at, double lo, double hi, double step) {
  std::sort(at.begin(), at.end());
  const double tol = 1e-9 * (1.0 + std::abs(lo) + std::abs(hi));
  std::vector<double> out;
  for (double v : at)
    if (out.empty() || v - out.back() > tol) out.push_back(v);
  std::vector<double> refined{out.front()};
  for (size_t i = 1; i < out.size(); ++i) {
    const double gap = out[i] - out[i - 1];
    const int parts = static_cast<int>(std::ceil(gap / step - 1e-9));
    for (int k = 1; k < parts; ++k) refined.push_back(out[i - 1] + gap * k / parts);
    refined.push_back(out[i]);
  }
  return refined;
}

// The lattice's planes per axis: about 16 intervals per axis at least, the obstacles' planes (a
// hair beyond their boxes) on top. Lattices beyond a few hundred thousand points are coarsened (a
// hint is not worth seconds): first the refinement, then, with many obstacles, their planes thinned
// to a spacing that fits. Every lattice edge is still checked exactly, so a route stays clear; only
// narrow openings may be missed. Empty when even the coarsest lattice is too large.
std::optional<std::array<std::vector<double>, 3>> lattice_axes(const Scene& scene, size_t obstacles,
                                                               const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                                               const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                                                               double hair) {
  constexpr size_t kMaxPoints = 300000;
  std::array<std::vector<double>, 3> axis;
  size_t points = 0;
  for (double parts = 16; parts >= 2; parts /= 2) {
    points = 1;
    for (int c = 0; c < 3; ++c) {
      std::vector<double> at{lo[c], hi[c], from[c], to[c]};
      for (size_t i = 0; i < obstacles; ++i)
        for (double v : {scene.box(i).lo[c] - hair, scene.box(i).hi[c] + hair})
          if (v > lo[c] && v < hi[c]) at.push_back(v);
      axis[c] = planes(at, lo[c], hi[c], std::max((hi[c] - lo[c]) / parts, 1e-12));
      points *= axis[c].size();
    }
    if (points <= kMaxPoints) break;
  }
  for (double share = 256; points > kMaxPoints && share >= 4; share /= 2) {
    points = 1;
    for (int c = 0; c < 3; ++c) {
      std::vector<double> kept;
      const double gap = (hi[c] - lo[c]) / share;
      for (double v : axis[c])
        if (kept.empty() || v == hi[c] || v == from[c] || v == to[c] || v - kept.back() >= gap) kept.push_back(v);
      axis[c] = std::move(kept);
      points *= axis[c].size();
    }
  }
  if (points > kMaxPoints) return std::nullopt;
  return axis;
}

// The lattice path's corners shortened: from each corner straight to the farthest one still in
// sight (the start left out, the end kept).
std::vector<Eigen::Vector3d> shortened(const Scene& scene, const std::vector<Eigen::Vector3d>& path) {
  std::vector<Eigen::Vector3d> corners;
  for (size_t at = 0; at + 1 < path.size();) {
    size_t next = path.size() - 1;
    while (next > at + 1 && !scene.visible(path[at], path[next])) --next;
    if (next + 1 < path.size()) corners.push_back(path[next]);
    at = next;
  }
  return corners;
}

}  // namespace

std::vector<Eigen::Vector3d> route_in_space(const std::vector<Prism>& prisms, const Eigen::Vector3d& lo_in,
                                            const Eigen::Vector3d& hi_in, const Eigen::Vector3d& from,
                                            const Eigen::Vector3d& to, bool* found) {
  if (found) *found = false;
  if (const Scene bare(prisms); !bare.free(from) || !bare.free(to)) return {};
  const Eigen::Vector3d lo = lo_in.cwiseMin(from).cwiseMin(to), hi = hi_in.cwiseMax(from).cwiseMax(to);
  if (!lo.allFinite() || !hi.allFinite()) return {};
  // The prisms grown by a hair, and the lattice's planes a hair beyond them: a segment along a
  // face would otherwise slip through the seam between two blocks that touch (each only touched,
  // their union crossed).
  const double hair = 1e-7 * (1.0 + (hi - lo).norm());
  std::vector<Prism> thick;
  for (const auto& p : prisms) thick.push_back({grow_by_box(p.base, hair, hair), p.z_lo - hair, p.z_hi + hair});
  const Scene scene(thick);
  if (scene.visible(from, to)) {
    if (found) *found = true;
    return {};
  }
  const auto lattice = lattice_axes(scene, prisms.size(), lo, hi, from, to, hair);
  if (!lattice) return {};
  const auto& axis = *lattice;
  const size_t nx = axis[0].size(), ny = axis[1].size(), nz = axis[2].size();
  auto id = [&](size_t i, size_t j, size_t k) { return (k * ny + j) * nx + i; };
  auto point = [&](size_t v) {
    return Eigen::Vector3d(axis[0][v % nx], axis[1][(v / nx) % ny], axis[2][v / (nx * ny)]);
  };
  auto index_of = [&](int c, double v) {
    return static_cast<size_t>(std::lower_bound(axis[c].begin(), axis[c].end(), v - 1e-12 * (1.0 + std::abs(v))) -
                               axis[c].begin());
  };
  const size_t start = id(index_of(0, from.x()), index_of(1, from.y()), index_of(2, from.z()));
  const size_t goal = id(index_of(0, to.x()), index_of(1, to.y()), index_of(2, to.z()));
  const size_t count = nx * ny * nz;
  std::vector<char> open(count);
  for (size_t v = 0; v < count; ++v) open[v] = scene.free(point(v));
  // Dijkstra over the 26-neighbourhood; an edge is taken only if the segment is free.
  std::vector<double> dist(count, std::numeric_limits<double>::infinity());
  std::vector<size_t> pred(count, count);
  using Item = std::pair<double, size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  dist[start] = 0.0;
  queue.push({0.0, start});
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v]) continue;
    if (v == goal) break;
    const long i = static_cast<long>(v % nx), j = static_cast<long>((v / nx) % ny), k = static_cast<long>(v / (nx * ny));
    const Eigen::Vector3d p = point(v);
    for (long dk = -1; dk <= 1; ++dk)
      for (long dj = -1; dj <= 1; ++dj)
        for (long di = -1; di <= 1; ++di) {
          const long a = i + di, b = j + dj, c = k + dk;
          if ((di | dj | dk) == 0 || a < 0 || b < 0 || c < 0 || a >= static_cast<long>(nx) ||
              b >= static_cast<long>(ny) || c >= static_cast<long>(nz))
            continue;
          const size_t w = id(a, b, c);
          if (!open[w]) continue;
          const Eigen::Vector3d q = point(w);
          const double nd = d + (q - p).norm();
          if (nd >= dist[w] || !scene.visible(p, q)) continue;
          dist[w] = nd;
          pred[w] = v;
          queue.push({nd, w});
        }
  }
  if (!std::isfinite(dist[goal])) return {};
  std::vector<Eigen::Vector3d> path;
  for (size_t v = goal; v != count; v = pred[v]) path.push_back(point(v));
  std::reverse(path.begin(), path.end());
  path.front() = from;
  path.back() = to;
  if (found) *found = true;
  return shortened(scene, path);
}

std::optional<Prism> other_side_barrier(const std::vector<Prism>& prisms, const Eigen::Vector3d& from,
                                        const Eigen::Vector3d& to, const std::vector<Eigen::Vector3d>& corners,
                                        double reach) {
  const Eigen::Vector3d d = to - from;
  if (corners.empty() || !(d.norm() > 0) || !(reach > 0)) return std::nullopt;
  // The first obstacle on the straight way, and a point inside it on that way's side of the
  // ends (its base's vertex mean, at the ends' height clamped into its own).
  const Prism* first = nullptr;
  double at = std::numeric_limits<double>::infinity();
  for (const auto& p : prisms)
    if (const double t = entry(p, from, to); t < at) at = t, first = &p;
  if (!first || first->base.empty()) return std::nullopt;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& v : first->base) c.head<2>() += v;
  c.head<2>() /= static_cast<double>(first->base.size());
  c.z() = std::isfinite(first->z_lo) && std::isfinite(first->z_hi)
              ? 0.5 * (first->z_lo + first->z_hi)
              : std::clamp(0.5 * (from.z() + to.z()), first->z_lo, first->z_hi);
  // Where the route crosses the plane through c across the way: the side it passes c on.
  std::vector<Eigen::Vector3d> line{from};
  line.insert(line.end(), corners.begin(), corners.end());
  line.push_back(to);
  std::optional<Eigen::Vector3d> q;
  for (size_t i = 0; i + 1 < line.size() && !q; ++i) {
    const double s0 = (line[i] - c).dot(d), s1 = (line[i + 1] - c).dot(d);
    if (s0 <= 0 && s1 > 0) q = line[i] + (line[i + 1] - line[i]) * (-s0 / (s1 - s0));
  }
  if (!q) return std::nullopt;
  Eigen::Vector3d v = *q - c;
  v -= v.dot(d) / d.squaredNorm() * d;
  const Eigen::Vector2d way = d.head<2>();
  const double thin = 1e-3 * (1.0 + d.norm());
  Prism wall;
  std::vector<Eigen::Vector2d> pts;
  if (std::abs(v.z()) > v.head<2>().norm()) {
    // Over (or under) it: a sheet across the way from c's height up (down), as wide as `reach`.
    if (!(way.norm() > 0)) return std::nullopt;
    const Eigen::Vector2d t = way.normalized(), across(-t.y(), t.x());
    for (double sa : {-1.0, 1.0})
      for (double st : {-1.0, 1.0}) pts.push_back(c.head<2>() + sa * reach * across + st * thin * t);
    wall.z_lo = v.z() > 0 ? c.z() : -std::numeric_limits<double>::infinity();
    wall.z_hi = v.z() > 0 ? std::numeric_limits<double>::infinity() : c.z();
  } else {
    // Beside it: a wall at every height from c out to `reach` on the route's side.
    if (!(v.head<2>().norm() > 0)) return std::nullopt;
    const Eigen::Vector2d n = v.head<2>().normalized(), t(-n.y(), n.x());
    for (double sn : {0.0, 1.0})
      for (double st : {-1.0, 1.0}) pts.push_back(c.head<2>() + sn * reach * n + st * thin * t);
    wall.z_lo = -std::numeric_limits<double>::infinity();
    wall.z_hi = std::numeric_limits<double>::infinity();
  }
  wall.base = convex_hull(pts);
  return wall;
}

}  // namespace marsyn::planning
