#include "marsyn/core/verification/broad_phase.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace marsyn {

using planning::Requirement;

Eigen::Vector2d nearest_on_polygon(const planning::Polygon& poly, const Eigen::Vector2d& p) {
  Eigen::Vector2d best = poly.front();
  double bd = 1e300;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d a = poly[i], b = poly[(i + 1) % poly.size()], ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const Eigen::Vector2d q = a + t * ab;
    if ((q - p).squaredNorm() < bd) {
      bd = (q - p).squaredNorm();
      best = q;
    }
  }
  return best;
}

planning::Point nearest_on_obstacle(const Obstacle& o, const planning::Point& p) {
  const Eigen::Vector2d xy(p.x(), p.y()), side = nearest_on_polygon(o.vertices, xy);
  if (!o.z_bounded()) return {side.x(), side.y(), p.z()};
  // The side's nearest point at the clamped height, or a cap's above or below p when p is over
  // the polygon, whichever is nearer.
  const planning::Point s(side.x(), side.y(), std::clamp(p.z(), o.z_lo, o.z_hi));
  if (planning::signed_distance_two(o.vertices, xy) > 0) return s;
  const planning::Point cap(p.x(), p.y(), p.z() - o.z_lo < o.z_hi - p.z() ? o.z_lo : o.z_hi);
  return (cap - p).norm() < (s - p).norm() ? cap : s;
}

bool nearest_by_search(const Problem& pb, int i, const std::vector<planning::Point>& pts, planning::Point& target) {
  double bd = 1e300;
  for (const auto& o : pb.obstacles) {
    const planning::Point q = nearest_on_obstacle(o, pts[i]);
    if (planning::distance2(q - pts[i]) < bd) {
      bd = planning::distance2(q - pts[i]);
      target = q;
    }
  }
  if (pb.pairwise_collision)
    for (std::size_t j = 0; j < pts.size(); ++j)
      if (static_cast<int>(j) != i && planning::distance2(pts[j] - pts[i]) < bd) {
        bd = planning::distance2(pts[j] - pts[i]);
        target = pts[j];
      }
  return bd < 1e300;
}

namespace {

// Far above the rounding of any margin formula at this scale (a few ulps), far below any
// distance that matters: a lower bound must clear the running minimum by this much to skip.
double slack(double a, double b) { return 1e-9 * (1.0 + std::abs(a) + std::abs(b)); }

// The squared length of e in the order of additions the bounds below assume; within a few ulps of
// the sum distance2() roots (its own order may differ in space), far inside their margins.
double sum_squares(const planning::Point& e) { return e.x() * e.x() + e.y() * e.y() + e.z() * e.z(); }

// How far p is outside an axis-aligned box along x and y (0 inside along that axis): a lower
// bound of the distance to a prism over the box in 3-D too.
Eigen::Vector2d outside(const Eigen::Vector4d& box, const planning::Point& p) {
  return {std::max({box[0] - p.x(), p.x() - box[2], 0.0}), std::max({box[1] - p.y(), p.y() - box[3], 0.0})};
}

}  // namespace

BroadPhase::BroadPhase(const Problem& problem) : pb_(problem), pair_clear_(problem.largest_pair_clearance()) {
  plane_start_.push_back(0);
  for (const auto& o : problem.obstacles) {
    Eigen::Vector4d b(1e300, 1e300, -1e300, -1e300);
    for (const auto& v : o.vertices) {
      b = {std::min(b[0], v.x()), std::min(b[1], v.y()), std::max(b[2], v.x()), std::max(b[3], v.y())};
      scale_ = std::max(scale_, v.cwiseAbs().maxCoeff());
    }
    bbox_.push_back(b);
    // The edges' half-planes where some edge is slanted (for a box they bound as its own box
    // does): PolygonEdges' outward normals of the counter-clockwise polygon (Obstacle's order, which
    // the margins assume too); a repeated vertex's NaN normal gives none.
    const planning::PolygonEdges edges(o.vertices);
    if (std::any_of(edges.e.begin(), edges.e.end(), [](const Eigen::Vector2d& e) { return e.x() != 0 && e.y() != 0; }))
      for (std::size_t k = 0; k < edges.a.size(); ++k) {
        const Eigen::Vector2d& normal = edges.normal[k];
        if (normal.allFinite()) planes_.emplace_back(normal.x(), normal.y(), normal.dot(edges.a[k]), 1.0 / normal.lpNorm<1>());
      }
    plane_start_.push_back(static_cast<int>(planes_.size()));
  }
}

// The rounding of n . p - n . a (a few ulps of |p| + |a|) and of the normal (its length and
// direction within an ulp or two: the line through a turns by that, which moves it an ulp or two
// of the polygon's extent at the far vertex) is far inside the slack every use below adds to
// the margins it compares (1e-9 of the largest coordinate).
double BroadPhase::plane_gap(int o, double x, double y, bool inf) const {
  double g = -1e300;
  for (int k = plane_start_[static_cast<size_t>(o)]; k < plane_start_[static_cast<size_t>(o) + 1]; ++k) {
    const Eigen::Vector4d& h = planes_[static_cast<size_t>(k)];
    const double d = h[0] * x + h[1] * y - h[2];
    g = std::max(g, inf ? d * h[3] : d);
  }
  return g;
}

double BroadPhase::plane_gap(int o, const Eigen::Vector4d& box, bool inf) const {
  double g = -1e300;
  for (int k = plane_start_[static_cast<size_t>(o)]; k < plane_start_[static_cast<size_t>(o) + 1]; ++k) {
    const Eigen::Vector4d& h = planes_[static_cast<size_t>(k)];
    // The box's corner least far along the normal.
    const double d = h[0] * (h[0] >= 0 ? box[0] : box[2]) + h[1] * (h[1] >= 0 ? box[1] : box[3]) - h[2];
    g = std::max(g, inf ? d * h[3] : d);
  }
  return g;
}

void BroadPhase::update(const std::vector<planning::Point>& p) {
  pts_ = &p;
  const int n = static_cast<int>(p.size());
  if (static_cast<int>(order_.size()) != n) {
    order_.resize(static_cast<size_t>(n));
    std::iota(order_.begin(), order_.end(), 0);
    place_.assign(static_cast<size_t>(n), 0);
  }
  // The adversary's lists (nearest_target) stand while every agent stays within moved_ of its
  // anchor; a list that could not decide, or a point not finite, has them rebuilt.
  if (lists_ready_ && (stale_ || static_cast<int>(anchor_.size()) != n)) lists_ready_ = false;
  // One pass: the points' finiteness (a sum of the coordinates minus itself is 0 only when every
  // one is finite; a sum that overflows on finite points also fails, which only costs the
  // skipping) and, while the lists stand, the farthest move from the anchors. The largest
  // distance as the square root of the largest sum of squares (one root, not one per agent; the
  // correctly rounded root is monotone): distance2()'s own value in the plane, within its
  // rounding in space, far inside the slack the bounds carry.
  double sum = 0, moved2 = 0;
  if (lists_ready_) {
    for (int i = 0; i < n; ++i) {
      const planning::Point& q = p[static_cast<size_t>(i)];
      const planning::Point e = q - anchor_[static_cast<size_t>(i)];
      sum += q.x() + q.y() + q.z();
      moved2 = std::max(moved2, sum_squares(e));
    }
  } else {
    for (int i = 0; i < n; ++i) sum += p[static_cast<size_t>(i)].x() + p[static_cast<size_t>(i)].y() + p[static_cast<size_t>(i)].z();
  }
  finite_ = sum - sum == 0;
  if (!finite_) lists_ready_ = false;
  if (lists_ready_) moved_ = std::sqrt(moved2);
  // The order along x is brought up to date where it is read (sort()): the adversary's lists
  // mostly decide without it.
  sorted_ = false;
}

void BroadPhase::sort() const {
  if (sorted_ || !finite_) return;
  const std::vector<planning::Point>& p = *pts_;
  const int n = static_cast<int>(p.size());
  // Insertion sort from the last order (about linear: the points move little between sorts).
  for (int a = 1; a < n; ++a) {
    const int v = order_[static_cast<size_t>(a)];
    int b = a;
    for (; b > 0 && p[static_cast<size_t>(order_[static_cast<size_t>(b - 1)])].x() > p[static_cast<size_t>(v)].x(); --b)
      order_[static_cast<size_t>(b)] = order_[static_cast<size_t>(b - 1)];
    order_[static_cast<size_t>(b)] = v;
  }
  for (int a = 0; a < n; ++a) place_[static_cast<size_t>(order_[static_cast<size_t>(a)])] = a;
  sorted_ = true;
}

long BroadPhase::rank(const Requirement& q) const {
  const long n = static_cast<long>(pb_.body_count()), obstacles = static_cast<long>(pb_.obstacles.size());
  const long pairs = pb_.pairwise_collision ? n * (n - 1) / 2 : 0;
  switch (q.kind) {
    case Requirement::Obstacle: return q.a * obstacles + q.b;
    case Requirement::Collision: return n * obstacles + q.a * (2 * n - q.a - 1) / 2 + (q.b - q.a - 1);
    case Requirement::Formation: break;
  }
  return n * obstacles + pairs + q.index;
}

void BroadPhase::fold_one(const Requirement& q, const std::vector<planning::Point>& p, double& slot, double& best,
                          long& best_rank, Requirement* worst) const {
  const double v = planning::requirement_margin(pb_, q, p);
  slot = std::min(slot, v);
  if (v < best || (v == best && best_rank >= 0 && rank(q) < best_rank)) {
    best = v;
    best_rank = rank(q);
    if (worst) *worst = q;
  }
}

bool BroadPhase::obstacle_clears(const StepMargins& run, int i, int o, const planning::Point& at) const {
  // Outside its bounding box, a point is at least as far from the obstacle as from the box.
  const Eigen::Vector2d g = outside(bbox_[static_cast<size_t>(o)], at);
  const bool inf = pb_.delta_norm == Norm::Inf;
  const double d = inf ? g.maxCoeff() : g.norm();  // > 0 outside the box; no bound inside it
  const double clear = run.obstacle + slack(run.obstacle, scale_ + at.cwiseAbs().maxCoeff());
  const double delta = pb_.obstacle_clearance(i);
  if (d > 0 && d - delta > clear) return true;
  // A slanted edge's half-plane: a bound inside the box too (asked only where the box's fails).
  if (!slanted(o)) return false;
  const double h = plane_gap(o, at.x(), at.y(), inf);
  return h > 0 && h - delta > clear;
}

// (Inlined: it is read once per candidate pair, and its call cost more than its arithmetic.)
[[gnu::always_inline]] inline double BroadPhase::pair_reach(const StepMargins& run) const {
  return run.collision + pair_clear_ + slack(run.collision, pair_clear_);
}

bool BroadPhase::accumulate(StepMargins& run, Requirement* worst, planning::Moment when) const {
  sort();
  const std::vector<planning::Point>& p = *pts_;
  const int n = static_cast<int>(p.size());
  // The lexicographically smallest (margin, rank) evaluated below the minimum before this state:
  // step()'s strict-less scan in requirement order names exactly that one.
  double best = run.min();
  long best_rank = -1;
  auto fold = [&](const Requirement& q, double& slot) { fold_one(q, p, slot, best, best_rank, worst); };
  const bool windowed = when.k >= 0 && windows_ && windows_->any();
  for (int i = 0; i < n; ++i)
    for (int o = 0; o < static_cast<int>(bbox_.size()); ++o) {
      if (windowed && !windows_->binds(pb_.body_agent(i), o, when)) continue;
      if (obstacle_clears(run, i, o, p[static_cast<size_t>(i)])) continue;
      fold({Requirement::Obstacle, i, o}, run.obstacle);
    }
  if (pb_.pairwise_collision) {
    // A pair is at least as far apart as along either axis, in both norms.
    auto reach = [&] { return pair_reach(run); };
    for (int a = 0; a < n; ++a) {
      const int i = finite_ ? order_[static_cast<size_t>(a)] : a;
      double r = reach();
      for (int b = a + 1; b < n; ++b) {
        const int j = finite_ ? order_[static_cast<size_t>(b)] : b;
        const planning::Point d = p[static_cast<size_t>(j)] - p[static_cast<size_t>(i)];
        if (finite_ && d.x() > r) break;  // sorted: every later one is farther along x
        if (finite_ && std::abs(d.y()) > r) continue;
        if (pb_.body_agent(i) == pb_.body_agent(j)) continue;  // one agent's own bodies
        fold({Requirement::Collision, std::min(i, j), std::max(i, j)}, run.collision);
        r = reach();
      }
    }
  }
  for (int q = 0; q < static_cast<int>(pb_.formation.size()); ++q)
    fold({Requirement::Formation, pb_.formation[static_cast<size_t>(q)].i, pb_.formation[static_cast<size_t>(q)].j, q},
         run.formation);
  return best_rank >= 0;
}

void BroadPhase::window(const std::vector<std::vector<planning::Point>>& states, int count, const StepMargins& run,
                        planning::Moment when) {
  const int n = pb_.body_count();
  boxes_.resize(static_cast<size_t>(n));
  bool finite = true;
  for (int i = 0; i < n; ++i) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    double xl = kInf, yl = kInf, xh = -kInf, yh = -kInf;
    // sum - sum is 0 only when every coordinate is finite (an inf or NaN makes it NaN; a sum
    // that overflows on finite points also fails, which only costs the skipping).
    double sum = 0;
    for (int s = 0; s < count; ++s) {
      const planning::Point& q = states[static_cast<size_t>(s)][static_cast<size_t>(i)];
      sum += q.x() + q.y() + q.z();
      xl = std::min(xl, q.x());
      yl = std::min(yl, q.y());
      xh = std::max(xh, q.x());
      yh = std::max(yh, q.y());
    }
    finite = finite && sum - sum == 0;
    boxes_[static_cast<size_t>(i)] = {xl, yl, xh, yh};
  }
  window_from_boxes(states, count, finite, run, when);
}

void BroadPhase::window(const std::vector<std::vector<planning::Point>>& states, std::span<const Eigen::Vector4d> boxes,
                        bool finite, const StepMargins& run, planning::Moment when) {
  boxes_.assign(boxes.begin(), boxes.end());
  window_from_boxes(states, static_cast<int>(states.size()), finite, run, when);
}

void BroadPhase::window_from_boxes(const std::vector<std::vector<planning::Point>>& states, int count, bool finite,
                                   const StepMargins& run, planning::Moment when) {
  window_ = &states;
  candidates_.clear();
  const int n = pb_.body_count();
  double mag = 0;  // the largest coordinate: the slack's scale for a difference of two
  for (const Eigen::Vector4d& b : boxes_) mag = std::max(mag, b.cwiseAbs().maxCoeff());
  const bool inf = pb_.delta_norm == Norm::Inf;
  const double delta = pair_clear_;
  // Formation pairs (planar: every point's z is 0, so x and y hold the whole distance): over the
  // window the pair's difference p_i - p_j (the very subtraction the margin takes) stays in its
  // box, so the distance lies between the box's nearest and farthest points from the origin, and
  // the margin mu - |d - lambda| is at least mu less the larger of lambda - nearest and farthest -
  // lambda (the deviation is convex in d). The difference's box, not the two agents' boxes: a
  // formation moves together. A pair whose bound clears the formation minimum by the slack (far
  // above the roots' rounding) cannot lower or tie it at any state of the window.
  formation_candidates_.clear();
  for (int q = 0; q < static_cast<int>(pb_.formation.size()); ++q) {
    const FormationPair& f = pb_.formation[static_cast<size_t>(q)];
    if (finite && pb_.workspace_dim < 3 && count > 0) {
      constexpr double kInf = std::numeric_limits<double>::infinity();
      double xl = kInf, yl = kInf, xh = -kInf, yh = -kInf;
      for (int s = 0; s < count; ++s) {
        const std::vector<planning::Point>& p = states[static_cast<size_t>(s)];
        const planning::Point d = p[static_cast<size_t>(f.i)] - p[static_cast<size_t>(f.j)];
        xl = std::min(xl, d.x());
        xh = std::max(xh, d.x());
        yl = std::min(yl, d.y());
        yh = std::max(yh, d.y());
      }
      const double nx = std::max({xl, -xh, 0.0}), ny = std::max({yl, -yh, 0.0});
      const double fx = std::max(xh, -xl), fy = std::max(yh, -yl);
      const double near = std::sqrt(nx * nx + ny * ny), far = std::sqrt(fx * fx + fy * fy);
      const double lb = f.mu - std::max(f.lambda - near, far - f.lambda);
      if (lb > run.formation + slack(run.formation, f.lambda + f.mu + mag)) continue;
    }
    formation_candidates_.push_back(q);
  }
  const bool windowed = when.k >= 0 && windows_ && windows_->any();
  for (int i = 0; i < n; ++i) {
    const double obstacle_delta = pb_.obstacle_clearance(i);
    for (int o = 0; o < static_cast<int>(bbox_.size()); ++o) {
      if (windowed && !windows_->binds(pb_.body_agent(i), o, when)) continue;
      // Every point of the agent's box is at least as far from the obstacle as the two boxes
      // are apart along x and along y.
      const Eigen::Vector4d &a = boxes_[static_cast<size_t>(i)], &b = bbox_[static_cast<size_t>(o)];
      const Eigen::Vector2d g(std::max({b[0] - a[2], a[0] - b[2], 0.0}), std::max({b[1] - a[3], a[1] - b[3], 0.0}));
      const double d = inf ? g.maxCoeff() : g.norm(), clear = run.obstacle + slack(run.obstacle, scale_ + mag);
      if (finite && d > 0 && d - obstacle_delta > clear) continue;
      // (Or the agent's whole box beyond a slanted edge's half-plane.)
      if (finite && slanted(o)) {
        const double h = plane_gap(o, a, inf);
        if (h > 0 && h - obstacle_delta > clear) continue;
      }
      candidates_.push_back({Requirement::Obstacle, i, o});
    }
  }
  if (!pb_.pairwise_collision) return;
  if (static_cast<int>(box_order_.size()) != n) {
    box_order_.resize(static_cast<size_t>(n));
    std::iota(box_order_.begin(), box_order_.end(), 0);
  }
  if (!finite) {
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        if (pb_.body_agent(i) != pb_.body_agent(j)) candidates_.push_back({Requirement::Collision, i, j});
    return;
  }
  // By increasing x_lo (insertion sort from the last window's order: the boxes move little).
  for (int a = 1; a < n; ++a) {
    const int v = box_order_[static_cast<size_t>(a)];
    int b = a;
    for (; b > 0 && boxes_[static_cast<size_t>(box_order_[static_cast<size_t>(b - 1)])][0] > boxes_[static_cast<size_t>(v)][0]; --b)
      box_order_[static_cast<size_t>(b)] = box_order_[static_cast<size_t>(b - 1)];
    box_order_[static_cast<size_t>(b)] = v;
  }
  // Two points of the boxes are at least as far apart as the boxes along either axis, in both norms.
  const double r = run.collision + delta + slack(run.collision, delta + mag);
  for (int a = 0; a < n; ++a) {
    const int i = box_order_[static_cast<size_t>(a)];
    const Eigen::Vector4d& bi = boxes_[static_cast<size_t>(i)];
    for (int b = a + 1; b < n; ++b) {
      const int j = box_order_[static_cast<size_t>(b)];
      const Eigen::Vector4d& bj = boxes_[static_cast<size_t>(j)];
      if (bj[0] - bi[2] > r) break;  // sorted by x_lo: every later box is as far along x
      if (std::max(bj[1] - bi[3], bi[1] - bj[3]) > r) continue;
      if (pb_.body_agent(i) == pb_.body_agent(j)) continue;
      candidates_.push_back({Requirement::Collision, std::min(i, j), std::max(i, j)});
    }
  }
}

bool BroadPhase::accumulate_window(int s, StepMargins& run, Requirement* worst) const {
  const std::vector<planning::Point>& p = (*window_)[static_cast<size_t>(s)];
  double best = run.min();
  long best_rank = -1;
  auto fold = [&](const Requirement& q, double& slot) { fold_one(q, p, slot, best, best_rank, worst); };
  // The point-level rules of accumulate() at this state, against the minima as they now stand.
  for (const Requirement& q : candidates_) {
    if (q.kind == Requirement::Obstacle) {
      if (!obstacle_clears(run, q.a, q.b, p[static_cast<size_t>(q.a)])) fold(q, run.obstacle);
      continue;
    }
    const planning::Point d = p[static_cast<size_t>(q.b)] - p[static_cast<size_t>(q.a)];
    const double r = pair_reach(run);
    if (!(std::abs(d.x()) > r || std::abs(d.y()) > r)) fold(q, run.collision);
  }
  for (int q : formation_candidates_)
    fold({Requirement::Formation, pb_.formation[static_cast<size_t>(q)].i, pb_.formation[static_cast<size_t>(q)].j, q},
         run.formation);
  return best_rank >= 0;
}

namespace {

// Agent j at q as the nearest so far to a point at `at` (ad its distance2, bj its index): smallest
// distance, then smallest index.
void consider(const planning::Point& at, const planning::Point& q, int j, double& ad, int& bj) {
  const planning::Point e = q - at;
  // No square root where the squared distance alone is above ad^2 by far more than the rounding
  // of either sum (ad^2 normal: no underflow); the square root is monotone, so such an agent is
  // strictly farther in distance2() too.
  if (ad > 1e-100 && sum_squares(e) > ad * ad * (1.0 + 1e-12)) return;
  const double d = planning::distance2(e);
  if (d < ad || (d == ad && j < bj)) {
    ad = d;
    bj = j;
  }
}

}  // namespace

void BroadPhase::sweep_nearest(int i, double& ad, int& bj) const {
  sort();
  const std::vector<planning::Point>& p = *pts_;
  const planning::Point& at = p[static_cast<size_t>(i)];
  const int n = static_cast<int>(p.size());
  // Warm start: the agent nearest at the last sweep is usually still near, so the reach is short
  // from the first step (the result is the same from any start: an agent is passed over only when
  // its x or y gap alone exceeds the nearest distance found, plus the slack).
  if (static_cast<int>(last_nearest_.size()) != n) last_nearest_.assign(static_cast<size_t>(n), -1);
  if (const int j0 = last_nearest_[static_cast<size_t>(i)]; j0 >= 0 && j0 != i) consider(at, p[static_cast<size_t>(j0)], j0, ad, bj);
  const int mine = place_[static_cast<size_t>(i)];
  const int* order = order_.data();
  const double ax = at.x(), ay = at.y();
  // (The reach, ad plus the slack, is recomputed only when ad falls.) An agent farther along y
  // than the reach is passed over too (a crowd at one x is then not a distance each).
  double reach = ad + slack(ad, 0);
  for (int b = mine + 1; b < n && p[static_cast<size_t>(order[b])].x() - ax <= reach; ++b) {
    const planning::Point& q = p[static_cast<size_t>(order[b])];
    if (std::abs(q.y() - ay) > reach) continue;
    const double before = ad;
    consider(at, q, order[b], ad, bj);
    if (ad != before) reach = ad + slack(ad, 0);
  }
  for (int b = mine - 1; b >= 0 && ax - p[static_cast<size_t>(order[b])].x() <= reach; --b) {
    const planning::Point& q = p[static_cast<size_t>(order[b])];
    if (std::abs(q.y() - ay) > reach) continue;
    const double before = ad;
    consider(at, q, order[b], ad, bj);
    if (ad != before) reach = ad + slack(ad, 0);
  }
  last_nearest_[static_cast<size_t>(i)] = bj;
}

void BroadPhase::build_lists() const {
  sort();
  const std::vector<planning::Point>& p = *pts_;
  const int n = static_cast<int>(p.size());
  anchor_ = p;
  mag_ = 0;
  for (const planning::Point& q : p) mag_ = std::max(mag_, q.cwiseAbs().maxCoeff());
  radius_.assign(static_cast<size_t>(n), 0.0);
  list_start_.assign(static_cast<size_t>(n) + 1, 0);
  list_.clear();
  for (int i = 0; i < n; ++i) {
    double ad = 1e300;
    int bj = -1;
    sweep_nearest(i, ad, bj);
    // Room for the agents to move before the list must be rebuilt: half the nearest distance.
    const double r = 1.5 * ad;
    radius_[static_cast<size_t>(i)] = r;
    const planning::Point& at = p[static_cast<size_t>(i)];
    const int mine = place_[static_cast<size_t>(i)];
    for (int b = mine + 1; b < n && p[static_cast<size_t>(order_[static_cast<size_t>(b)])].x() - at.x() <= r; ++b)
      if (std::abs(p[static_cast<size_t>(order_[static_cast<size_t>(b)])].y() - at.y()) <= r) list_.push_back(order_[static_cast<size_t>(b)]);
    for (int b = mine - 1; b >= 0 && at.x() - p[static_cast<size_t>(order_[static_cast<size_t>(b)])].x() <= r; --b)
      if (std::abs(p[static_cast<size_t>(order_[static_cast<size_t>(b)])].y() - at.y()) <= r) list_.push_back(order_[static_cast<size_t>(b)]);
    list_start_[static_cast<size_t>(i) + 1] = static_cast<int>(list_.size());
  }
  answer_.assign(static_cast<size_t>(n), -1);
  second_.assign(static_cast<size_t>(n), -1);
  others_.assign(static_cast<size_t>(n), 0.0);
  moved_ = 0;
  lists_ready_ = true;
  stale_ = false;
}

// (Inlined into nearest_target: the adversary asks it for every agent at every substep.)
[[gnu::always_inline]] inline bool BroadPhase::nearest_from_candidates(int i, double& ad, double& e2, int& bj) const {
  const int j0 = answer_[static_cast<size_t>(i)], j1 = second_[static_cast<size_t>(i)];
  if (j0 < 0) return false;
  const std::vector<planning::Point>& p = *pts_;
  const planning::Point& at = p[static_cast<size_t>(i)];
  // The nearer of the two candidates, without a square root where their sums of squares differ by
  // a relative 1e-12: far above the sums' few ulps of rounding, and the correctly rounded root is
  // monotone and halves a relative gap, so the smaller sum's distance2() is then strictly smaller.
  // Otherwise (near ties, or sums out of the normal range) both distances as distance2() gives
  // them, the smaller index winning a tie.
  int b = j0;
  double eb = sum_squares(p[static_cast<size_t>(j0)] - at), exact = -1.0;
  if (j1 >= 0) {
    const double e1 = sum_squares(p[static_cast<size_t>(j1)] - at);
    const bool normal = eb > 1e-200 && e1 > 1e-200 && eb < 1e200 && e1 < 1e200;
    const bool first = eb * (1.0 + 1e-12) < e1, second = e1 * (1.0 + 1e-12) < eb;
    if (normal && (first || second)) {
      // Without a branch on which (a coin toss between symmetric neighbours): the smaller sum,
      // and j1 where it is j1's.
      b = j0 ^ ((j0 ^ j1) & -static_cast<int>(second));
      eb = std::min(eb, e1);
    } else {
      const double d0 = planning::distance2(p[static_cast<size_t>(j0)] - at), d1 = planning::distance2(p[static_cast<size_t>(j1)] - at);
      const bool one = d1 < d0 || (d1 == d0 && j1 < j0);
      b = one ? j1 : j0;
      eb = one ? e1 : eb;
      exact = one ? d1 : d0;
    }
  }
  // The answer stands while it is nearer, by the slack, than a lower bound of every other agent's
  // distance: an agent on the list (other than the two) was at least others_ away when the list
  // was last scanned, and each of the two has moved at most moved_ from the anchor since, so at
  // most moved_ + (moved_ then) from where it was (folded into others_); one off the list is
  // farther than r - 2 moved_. Then no other agent can win or tie, and the scan would give this
  // answer. The test d + slack(d, M) < others, i.e. d (1 + 1e-9) < a, on the sum of squares:
  // d^2 (1 + 1e-9)^2 < a^2 with room to spare for the sum's and the products' rounding.
  const double r = radius_[static_cast<size_t>(i)];
  const double others = std::min(others_[static_cast<size_t>(i)], r) - 2.0 * moved_;
  const double a = others - 1e-9 * (1.0 + mag_ + moved_ + r);
  if (!(a > 1e-100 && eb < 1e200 && eb * (1.0 + 3e-9) < a * a)) return false;
  ad = exact;
  e2 = eb;
  bj = b;
  return true;
}

bool BroadPhase::nearest_from_list(int i, double& ad, int& bj) const {
  const std::vector<planning::Point>& p = *pts_;
  const planning::Point& at = p[static_cast<size_t>(i)];
  const double r = radius_[static_cast<size_t>(i)];
  // The three smallest sums of squares on the list and whose the first two are (the candidates
  // and a lower bound of the others' distances for the test above).
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double s1 = kInf, s2 = kInf, s3 = kInf;
  int j1 = -1, j2 = -1;
  for (int k = list_start_[static_cast<size_t>(i)]; k < list_start_[static_cast<size_t>(i) + 1]; ++k) {
    const int j = list_[static_cast<size_t>(k)];
    const planning::Point& q = p[static_cast<size_t>(j)];
    const double eq = sum_squares(q - at);
    if (eq < s1) {
      s3 = s2;
      s2 = s1;
      j2 = j1;
      s1 = eq;
      j1 = j;
    } else if (eq < s2) {
      s3 = s2;
      s2 = eq;
      j2 = j;
    } else if (eq < s3) {
      s3 = eq;
    }
    consider(at, q, j, ad, bj);
  }
  // An agent off the list was farther than the radius along x or y at the anchor, and each of
  // the two has moved at most moved_ since: it is now farther than radius - 2 moved_, which
  // must clear the nearest distance on the list by the slack (then it can neither win nor tie).
  const bool decided = bj >= 0 && r - 2.0 * moved_ > ad + slack(ad, mag_ + moved_ + r);
  answer_[static_cast<size_t>(i)] = decided ? bj : -1;
  if (decided) {
    // The candidates: the answer and the nearest other by sum of squares. Every other list agent's
    // sum is at least the smallest of the first three's that is neither (j1 is always one). (The
    // square root of a rounded sum of squares is within a few ulp of the distance: 1e-12 below it
    // is a lower bound, far inside the slack.)
    const int c1 = j1 != bj ? j1 : j2;
    const double rest = j2 == bj || j2 == c1 ? s3 : s2;
    second_[static_cast<size_t>(i)] = c1;
    others_[static_cast<size_t>(i)] = std::sqrt(rest) * (1.0 - 1e-12) - 2.0 * moved_;
  }
  return decided;
}

bool BroadPhase::nearest_target(int i, planning::Point& target) const {
  const std::vector<planning::Point>& p = *pts_;
  const planning::Point& at = p[static_cast<size_t>(i)];
  // The nearest other agent first (smallest distance, then smallest index): its distance bounds
  // the obstacles worth a polygon search, which is most of the cost where an agent is near.
  double ad = 1e300, e2 = 0;
  int bj = -1;
  if (pb_.pairwise_collision) {
    const int n = static_cast<int>(p.size());
    if (!finite_) {
      for (int j = 0; j < n; ++j)
        if (j != i) consider(at, p[static_cast<size_t>(j)], j, ad, bj);
    } else {
      // Each agent's list of the agents near it (a Verlet list), kept while the agents move
      // little; the sorted sweep where the list cannot decide, and the lists rebuilt at the next
      // substep.
      if (!lists_ready_ && n >= 2) build_lists();
      if (!(lists_ready_ && (nearest_from_candidates(i, ad, e2, bj) || nearest_from_list(i, ad, bj)))) {
        ad = 1e300;
        bj = -1;
        sweep_nearest(i, ad, bj);
        stale_ = true;
      }
    }
  }
  // An obstacle wins at a distance up to the agent's (the full search scans obstacles first and
  // takes an agent only when strictly nearer); among obstacles, the first of the smallest. One
  // whose bounding box is farther than the agent by more than the slack cannot win.
  double bd = 1e300;
  bool found = false;
  if (!bbox_.empty()) {
    // The agent's squared distance (or, decided without it, its sum of squares: within ulps).
    const double agent2 = ad >= 0 ? ad * ad : e2;
    const double c = 1e-9 * (1.0 + scale_ + at.cwiseAbs().maxCoeff());
    // The obstacle with the nearest box is searched first, so that its distance skips the
    // farther boxes before them in index order; the answer stays the first (by index) of the
    // smallest distances, whatever the order.
    const std::size_t M = bbox_.size();
    box2_.resize(M);
    std::size_t first = 0;
    for (std::size_t o = 0; o < M; ++o) {
      box2_[o] = outside(bbox_[o], at).squaredNorm();
      if (box2_[o] < box2_[first]) first = o;
    }
    std::size_t bo = M;
    for (std::size_t step = 0; step <= M; ++step) {
      const std::size_t o = step == 0 ? first : step - 1;
      if (step > 0 && o == first) continue;
      // Skipped when the box's distance lb > B + slack(B, scale) = B (1 + 1e-9) + c for some B at
      // least the nearest so far (the slack grows with B, so this is the test on min(bd, ad) or
      // stronger), squared without a root: (B (1 + 1e-9) + c)^2 <= B^2 ((1 + 1e-9)^2 + 2c) + 2c + c^2
      // (2B <= 1 + B^2, (1 + 1e-9) c <= 2c), and the factor 1 + 1e-12 for the sums' rounding.
      // A skipped obstacle is strictly farther than the nearest: it cannot tie either.
      const double b2 = std::min(bd * bd, agent2);
      const double skip2 = (b2 * (1.0 + 3e-9 + 2.0 * c) + 2.0 * c + c * c) * (1.0 + 1e-12);
      if (box2_[o] > skip2) continue;
      // Or a slanted edge's half-plane (the Euclidean distance, as the search's), asked only here.
      if (slanted(static_cast<int>(o))) {
        const double h = plane_gap(static_cast<int>(o), at.x(), at.y(), false);
        if (h > 0 && h * h > skip2) continue;
      }
      const planning::Point q = nearest_on_obstacle(pb_.obstacles[o], at);
      const double d = planning::distance2(q - at);
      if (d < bd || (d == bd && o < bo)) {
        bd = d;
        bo = o;
        target = q;
        found = true;
      }
    }
  }
  if (bj >= 0) {
    // (The list may decide the nearest agent without its distance: only an obstacle needs it.)
    if (found && ad < 0) ad = planning::distance2(p[static_cast<size_t>(bj)] - at);
    if (!(found && bd <= ad)) {
      target = p[static_cast<size_t>(bj)];
      return true;
    }
  }
  return found;
}

}  // namespace marsyn
