#include "marsyn/core/planning/margins.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "marsyn/core/planning/constraints.hpp"  // workspace_point_jacobian
#include "marsyn/directed_rounding.hpp"
#include "marsyn/interval.hpp"

namespace marsyn::planning {

namespace {

WorkspaceMargin linear_margin(const AgentSpec& a) {
  WorkspaceMargin m;
  const auto& ws = a.workspace;
  m.x = ws.index[0] >= 0 ? a.tube.eps[ws.index[0]] : 0.0;
  m.y = ws.index[1] >= 0 ? a.tube.eps[ws.index[1]] : 0.0;
  if (ws.dim() == 3) m.z = ws.index[2] >= 0 ? a.tube.eps[ws.index[2]] : 0.0;
  return m;
}

// max over p in P, q in Q of |p - q| per coordinate, with P = enclosure over the grown box and
// Q = enclosure over the nominal cell. Boxes and differences are rounded outward (no mode switch:
// directed_rounding.hpp), so the margin is never below the exact one.
void spread(const Interval* big, const Interval* small, WorkspaceMargin& m) {
  for (int c = 0; c < 2; ++c) {
    const double v = std::max(fast_detail::sub_up(big[c].upper(), small[c].lower()),
                              fast_detail::sub_up(small[c].upper(), big[c].lower()));
    (c == 0 ? m.x : m.y) = std::max(c == 0 ? m.x : m.y, v);
  }
}

}  // namespace

WorkspaceMargin margin_at(const AgentSpec& a, const Eigen::VectorXd& x) { return margin_at(a, x.data()); }

WorkspaceMargin margin_at(const AgentSpec& a, const double* x) {
  if (a.workspace.linear()) return linear_margin(a);
  const int n = a.n();
  std::vector<Interval> box(n), point(n);
  for (int i = 0; i < n; ++i) {
    box[i] = Interval(fast_detail::sub_down(x[i], a.tube.eps[i]), fast_detail::add_up(x[i], a.tube.eps[i]));
    point[i] = Interval(x[i]);
  }
  Interval big[2], small[2];
  a.dynamics->footprint(a.workspace.footprint, box.data(), big);
  a.dynamics->footprint(a.workspace.footprint, point.data(), small);
  WorkspaceMargin m;
  spread(big, small, m);
  return m;
}

MarginTable::MarginTable(const AgentSpec& a, const Box& region, int cells_per_dim) : agent_(&a) {
  if (a.workspace.linear()) {
    linear_ = linear_margin(a);
    return;
  }
  const int n = a.n();
  // Split only the coordinates the footprint reads: an interval evaluation with one coordinate
  // replaced by a wide interval is unchanged exactly when the footprint ignores it.
  std::vector<Interval> probe(n);
  for (int i = 0; i < n; ++i) probe[i] = Interval(region.center()[i]);
  Interval base[2];
  a.dynamics->footprint(a.workspace.footprint, probe.data(), base);
  for (int i = 0; i < n; ++i) {
    auto p = probe;
    p[i] = Interval(region.lo[i], region.hi[i]);
    Interval out[2];
    a.dynamics->footprint(a.workspace.footprint, p.data(), out);
    for (int c = 0; c < 2; ++c)
      if (out[c].lower() != base[c].lower() || out[c].upper() != base[c].upper()) {
        split_.push_back(i);
        break;
      }
  }
  if (split_.empty()) {  // a constant footprint
    linear_ = evaluate(0);
    return;
  }
  lo_ = region.lo;
  hi_ = region.hi;
  // A footprint reading more than two coordinates (a tractor's hitch: x, y, heading, articulation)
  // would need a table too coarse to be useful (8 cells per coordinate made a 9 m lane need 19 m:
  // each cell's own width adds to its bound); the bound at the state itself is the check's own.
  if (split_.size() > 2) {
    pointwise_ = true;
    return;
  }
  k_ = cells_per_dim;
  long total = 1;
  for (size_t s = 0; s < split_.size(); ++s) total *= k_;
  cells_.resize(total);
  done_ = std::make_unique<std::atomic<bool>[]>(total);
  for (long i = 0; i < total; ++i) done_[i].store(false);
}

WorkspaceMargin MarginTable::evaluate(long idx) const {
  const AgentSpec& a = *agent_;
  const int n = a.n();
  std::vector<Interval> cell(n), grown(n);
  for (int i = 0; i < n; ++i) cell[i] = Interval(lo_.size() ? lo_[i] : 0.0, hi_.size() ? hi_[i] : 0.0);
  long r = idx;
  for (int s : split_) {
    const int j = static_cast<int>(r % k_);
    r /= k_;
    cell[s] = Interval(edge(s, j), edge(s, j + 1));
  }
  for (int i = 0; i < n; ++i)
    grown[i] = Interval(fast_detail::sub_down(cell[i].lower(), a.tube.eps[i]), fast_detail::add_up(cell[i].upper(), a.tube.eps[i]));
  Interval big[2], small[2];
  a.dynamics->footprint(a.workspace.footprint, grown.data(), big);
  a.dynamics->footprint(a.workspace.footprint, cell.data(), small);
  WorkspaceMargin m;
  spread(big, small, m);
  return m;
}

double MarginTable::edge(int s, int j) const {
  // The same expression for the shared edge of neighbouring cells, so the cover has no gaps.
  return j == k_ ? hi_[s] : lo_[s] + j * ((hi_[s] - lo_[s]) / k_);
}

WorkspaceMargin MarginTable::at(const double* x) const {
  if (split_.empty()) return linear_;
  if (pointwise_) {
    // Clamped to the region as the cells are: outside it the state bounds are violated anyway.
    // (A planner asks this at every evaluation: no copy for a state inside the region.)
    const int n = agent_->n();
    bool inside = true;
    for (int i = 0; i < n && inside; ++i) inside = x[i] >= lo_[i] && x[i] <= hi_[i];
    if (inside) return margin_at(*agent_, x);
    std::vector<double> y(x, x + n);
    for (int i = 0; i < n; ++i) y[i] = std::clamp(y[i], lo_[i], hi_[i]);
    return margin_at(*agent_, y.data());
  }
  long idx = 0, stride = 1;
  for (int s : split_) {
    const double v = std::clamp(x[s], lo_[s], hi_[s]);
    int j = std::clamp(static_cast<int>((v - lo_[s]) / ((hi_[s] - lo_[s]) / k_)), 0, k_ - 1);
    // Rounding may put v just outside cell j: step to the neighbour that holds it.
    if (v < edge(s, j) && j > 0) --j;
    if (v > edge(s, j + 1) && j + 1 < k_) ++j;
    idx += j * stride;
    stride *= k_;
  }
  if (!done_[idx].load(std::memory_order_acquire)) {
    std::lock_guard<std::mutex> lock(fill_);
    if (!done_[idx].load(std::memory_order_relaxed)) {
      cells_[idx] = evaluate(idx);
      done_[idx].store(true, std::memory_order_release);
    }
  }
  return cells_[idx];
}

WorkspaceMargin MarginTable::max() const {
  if (split_.empty()) return linear_;
  WorkspaceMargin m;
  auto keep = [&m](const WorkspaceMargin& c) {
    m.x = std::max(m.x, c.x);
    m.y = std::max(m.y, c.y);
    m.z = std::max(m.z, c.z);
  };
  if (pointwise_) {
    // An estimate: the bounds at the region's centre, the start, the goal's centre, and the
    // centre moved to each end of every coordinate the footprint reads.
    const int n = agent_->n();
    Eigen::VectorXd c = 0.5 * (lo_ + hi_);
    for (int i = 0; i < n; ++i)
      if (!std::isfinite(c[i])) c[i] = agent_->x0[i];
    keep(at(c.data()));
    keep(at(agent_->x0.data()));
    Eigen::VectorXd g = agent_->goal.center();
    for (int i = 0; i < n; ++i)
      if (!std::isfinite(g[i])) g[i] = agent_->x0[i];
    keep(at(g.data()));
    for (int s : split_)
      for (double v : {lo_[s], hi_[s]}) {
        Eigen::VectorXd y = c;
        if (std::isfinite(v)) y[s] = v;
        keep(at(y.data()));
      }
    return m;
  }
  for (long i = 0; i < static_cast<long>(cells_.size()); ++i) keep(evaluate(i));
  return m;
}

WorkspaceMargin global_margin(const AgentSpec& a, const Box& region, int cells_per_dim) {
  return MarginTable(a, region, cells_per_dim).max();
}

double workspace_speed_bound(const AgentSpec& a, double horizon_s, double leg_speed) {
  const int n = a.n(), m = a.m();
  std::vector<Interval> x(n), u(m), f(n);
  Eigen::VectorXd centre(n);
  const Eigen::VectorXd goal = a.goal.center();
  for (int i = 0; i < n; ++i) {
    double lo = a.state_bounds.lo[i], hi = a.state_bounds.hi[i];
    const double g = std::isfinite(goal[i]) ? goal[i] : a.x0[i], span = std::abs(g - a.x0[i]) + 1.0;
    if (!std::isfinite(lo)) lo = std::min(a.x0[i], g) - span;
    if (!std::isfinite(hi)) hi = std::max(a.x0[i], g) + span;
    x[i] = Interval(lo, hi);
    centre[i] = 0.5 * (lo + hi);
  }
  for (int j = 0; j < m; ++j) u[j] = Interval(a.input_bounds.lo[j], a.input_bounds.hi[j]);
  a.dynamics->field(x.data(), u.data(), f.data());
  Eigen::VectorXd speed(n);
  for (int i = 0; i < n; ++i) speed[i] = std::max(std::abs(f[i].lower()), std::abs(f[i].upper()));
  double out = 0.0;
  const auto& ws = a.workspace;
  if (ws.linear()) {
    for (int c = 0; c < ws.dim(); ++c)
      if (ws.index[c] >= 0) out = std::max(out, speed[ws.index[c]]);
  } else {
    double p[2];
    std::vector<double> J(2 * n);
    workspace_point_jacobian(a, centre.data(), p, J.data());
    for (int c = 0; c < 2; ++c) {
      double v = 0.0;
      for (int i = 0; i < n; ++i) v += std::abs(J[c * n + i]) * speed[i];
      out = std::max(out, v);
    }
  }
  if (!std::isfinite(out)) return 0.0;
  // The box's worst case is far above what a plan does where the state box is wide (the crane's
  // rates): at most twice the average speed from the start to the goal over the horizon, or
  // twice the fastest leg of a mission where that is faster.
  if (horizon_s > 0) {
    double p0[kMaxWorkspaceDim] = {}, p1[kMaxWorkspaceDim] = {};
    if (goal.allFinite()) {
      workspace_point_jacobian(a, a.x0.data(), p0, nullptr);
      workspace_point_jacobian(a, goal.data(), p1, nullptr);
      const double mean = std::max({std::abs(p1[0] - p0[0]), std::abs(p1[1] - p0[1]), std::abs(p1[2] - p0[2])}) / horizon_s;
      out = std::min(out, 2.0 * std::max(mean, leg_speed));
    }
  }
  return out;
}

}  // namespace marsyn::planning
