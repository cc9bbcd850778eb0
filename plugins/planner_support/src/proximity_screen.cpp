#include "marsyn/planner_support/proximity_screen.hpp"

#include <algorithm>
#include <cmath>
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
  unscreened_.assign(constraints.size(), 1);
  for (int i = 0; i < static_cast<int>(constraints.size()); ++i) {
    const Constraint& c = *constraints[i];
    const double reach = c.pair_reach();
    const auto& s = c.support();
    if (!enabled || !std::isfinite(reach) || s.empty()) continue;
    const int a = agent_of.at(s.front()), b = agent_of.at(s.back());
    if (a == b) continue;
    pairs_.push_back({std::min(a, b), std::max(a, b), reach, i});
    unscreened_[i] = 0;
    widest_ = std::max(widest_, reach);
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

void ProximityScreen::mark(const double* x, std::vector<char>& near) const { mark(x, near, own_); }

void ProximityScreen::mark(const double* x, std::vector<char>& near, Buffers& b) const {
  near = unscreened_;
  if (pairs_.empty()) return;
  const int N = static_cast<int>(offsets_.size());
  b.px.resize(N);
  b.py.resize(N);
  b.order.resize(N);
  std::vector<double>& px_ = b.px;
  std::vector<double>& py_ = b.py;
  std::vector<int>& order_ = b.order;
  bool finite = true;
  for (int i = 0; i < N; ++i) {
    const AgentSpec& a = problem_.agents[i];
    double p[kMaxWorkspaceDim];  // x-y only: the max norm in x-y never exceeds the 3-D one
    workspace_point(*a.dynamics, a.workspace, x + offsets_[i], p);
    px_[i] = p[0];
    py_[i] = p[1];
    finite = finite && std::isfinite(p[0]) && std::isfinite(p[1]);
  }
  if (!finite) {  // no ordering to sweep: nothing is skipped
    std::fill(near.begin(), near.end(), 1);
    return;
  }
  std::iota(order_.begin(), order_.end(), 0);
  std::sort(order_.begin(), order_.end(), [&](int i, int j) { return px_[i] < px_[j]; });
  for (int s = 0; s < N; ++s) {
    const int i = order_[s];
    for (int t = s + 1; t < N; ++t) {
      const int j = order_[t];
      const double dx = px_[j] - px_[i];
      if (dx > widest_) break;  // sorted: every later agent is farther along x
      const double d = std::max(dx, std::abs(py_[j] - py_[i]));
      if (d > widest_) continue;
      const std::size_t key = static_cast<std::size_t>(std::min(i, j)) * N + std::max(i, j);
      for (int r = first_[key], e = r + count_[key]; r < e; ++r)
        if (d <= pairs_[r].reach) near[pairs_[r].index] = 1;
    }
  }
}

}  // namespace marsyn::planner_support
