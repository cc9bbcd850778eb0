#include "marsyn/planner_support/proximity_screen.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numeric>

namespace marsyn::planner_support {

ProximityScreen::ProximityScreen(const Problem& problem, const std::vector<const Constraint*>& constraints,
                                 bool enabled)
    : problem_(problem) {
  const ProductLayout layout(problem);
  const int N = static_cast<int>(problem.agents.size());
  offsets_.assign(layout.state.begin(), layout.state.end() - 1);
  std::vector<int> agent_of(layout.state_dim());
  for (int i = 0; i < N; ++i)
    for (int c = layout.state[i]; c < layout.state[i + 1]; ++c) agent_of[c] = i;
  size_ = static_cast<int>(constraints.size());
  for (int i = 0; i < size_; ++i) {
    const Constraint& c = *constraints[i];
    const double reach = c.pair_reach();
    const auto& s = c.support();
    const int a = s.empty() ? 0 : agent_of.at(s.front()), b = s.empty() ? 0 : agent_of.at(s.back());
    Region r{a, {0, 0}, {0, 0}, i, c.reach_decay()};
    if (enabled && !s.empty() && a == b && c.clear_outside(r.lo, r.hi)) {
      regions_.push_back(r);
      continue;
    }
    if (!enabled || !std::isfinite(reach) || s.empty() || a == b) {
      unscreened_.push_back(i);
      continue;
    }
    pairs_.push_back({std::min(a, b), std::max(a, b), reach, i, c.reach_decay()});
    widest_ = std::max(widest_, reach);
    slowest_ = std::min(slowest_, c.reach_decay());
  }
  std::sort(pairs_.begin(), pairs_.end(),
            [](const Pair& p, const Pair& q) { return p.a != q.a ? p.a < q.a : p.b < q.b; });
  first_.assign(static_cast<std::size_t>(N) * N, 0);
  count_.assign(static_cast<std::size_t>(N) * N, 0);
  for (int i = static_cast<int>(pairs_.size()) - 1; i >= 0; --i) {
    const std::size_t key = static_cast<std::size_t>(pairs_[i].a) * N + pairs_[i].b;
    first_[key] = i;
    ++count_[key];
  }
}

void ProximityScreen::near(const double* x, std::vector<int>& out, Buffers& b, double level) const {
  out.clear();
  if (!active()) {
    out = unscreened_;
    return;
  }
  const int N = static_cast<int>(offsets_.size());
  b.px.resize(N);
  b.py.resize(N);
  bool finite = true;
  for (int i = 0; i < N; ++i) {
    const AgentSpec& a = problem_.agents[i];
    double p[kMaxWorkspaceDim];  // x-y only: the max norm in x-y never exceeds the 3-D one
    workspace_point(*a.dynamics, a.workspace, x + offsets_[i], p);
    b.px[i] = p[0];
    b.py[i] = p[1];
    finite = finite && std::isfinite(p[0]) && std::isfinite(p[1]);
  }
  if (!finite) {  // no ordering to sweep: nothing is skipped
    out.resize(size_);
    std::iota(out.begin(), out.end(), 0);
    return;
  }
  b.hits.clear();
  for (const Region& r : regions_) {
    const double px = b.px[r.agent], py = b.py[r.agent], w = widening(level, r.decay);
    if (px >= r.lo[0] - w && px <= r.hi[0] + w && py >= r.lo[1] - w && py <= r.hi[1] + w) b.hits.push_back(r.index);
  }
  if (!pairs_.empty()) sweep_pairs(b, level);
  // Each pair is met once in the sweep and each region once: no index repeats.
  std::sort(b.hits.begin(), b.hits.end());
  std::merge(unscreened_.begin(), unscreened_.end(), b.hits.begin(), b.hits.end(), std::back_inserter(out));
}

// The pairs within reach (widened for `level`) at b.px, b.py, appended to b.hits.
void ProximityScreen::sweep_pairs(Buffers& b, double level) const {
  const double widest = widest_ + widening(level, slowest_);
  const int N = static_cast<int>(offsets_.size());
  // By x, by insertion from the last call's order (the set of pairs within reach does not
  // depend on how agents at equal x are ordered).
  std::vector<int>& order = b.order;
  if (static_cast<int>(order.size()) != N) {
    order.resize(N);
    std::iota(order.begin(), order.end(), 0);
  }
  for (int s = 1; s < N; ++s) {
    const int v = order[s];
    int t = s;
    for (; t > 0 && b.px[order[t - 1]] > b.px[v]; --t) order[t] = order[t - 1];
    order[t] = v;
  }
  for (int s = 0; s < N; ++s) {
    const int i = order[s];
    for (int t = s + 1; t < N; ++t) {
      const int j = order[t];
      const double dx = b.px[j] - b.px[i];
      if (dx > widest) break;  // sorted: every later agent is farther along x
      const double d = std::max(dx, std::abs(b.py[j] - b.py[i]));
      if (d > widest) continue;
      const std::size_t key = static_cast<std::size_t>(std::min(i, j)) * N + std::max(i, j);
      for (int r = first_[key], e = r + count_[key]; r < e; ++r)
        if (d <= pairs_[r].reach + widening(level, pairs_[r].decay)) b.hits.push_back(pairs_[r].index);
    }
  }
}

}  // namespace marsyn::planner_support
