#include "marsyn/core/planning/mission.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "marsyn/fast_interval.hpp"

namespace marsyn::planning {

namespace {

constexpr int kNoLimit = std::numeric_limits<int>::max() / 4;

// Stages are regions of the plane (a 3-D workspace's x-y, at every height): the workspace
// point's x and y.
Eigen::Vector2d xy_point(const AgentSpec& a, const double* x) {
  double p[kMaxWorkspaceDim];
  workspace_point3<double>(*a.dynamics, a.workspace, x, p);
  return {p[0], p[1]};
}

Eigen::Vector2d region_centre(const AgentSpec& a, const MissionStage& s) {
  if (s.is_polygon()) {
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (const auto& v : s.polygon) c += v;
    return c / static_cast<double>(s.polygon.size());
  }
  const Eigen::VectorXd x = s.box.center();
  Eigen::Vector2d p;
  p = xy_point(a, x.data());
  return p;
}

// The share of the travel done on arriving at each stage: straight lines through the regions'
// centres, from the start's workspace point to the goal's.
std::vector<double> straight_fractions(const AgentSpec& a) {
  const int S = static_cast<int>(a.stages.size());
  if (S == 0) return {};
  Eigen::Vector2d p0, pg;
  p0 = xy_point(a, a.x0.data());
  const Eigen::VectorXd gc = a.goal.center();
  pg = xy_point(a, gc.data());
  std::vector<double> L(S + 1, 0.0);
  Eigen::Vector2d prev = p0;
  for (int s = 0; s <= S; ++s) {
    const Eigen::Vector2d c = s < S ? region_centre(a, a.stages[s]) : pg;
    L[s] = (s > 0 ? L[s - 1] : 0.0) + (c - prev).norm();
    prev = c;
  }
  std::vector<double> f(S);
  for (int s = 0; s < S; ++s) f[s] = L[S] > 1e-12 ? L[s] / L[S] : (s + 1.0) / (S + 1.0);
  return f;
}

// Places agent a's visits at horizon T: stage s at the share f[s] of the travel (the horizon less
// the dwells), moved into the windows (fixed[s] >= 0 pins stage s there: a team's knot). Returns
// false (with why) when some window or the order cannot be met; k then holds the nearest knots
// found.
bool place(const AgentSpec& a, int T, const std::vector<double>& f, const std::vector<int>& fixed, std::vector<int>& k,
           std::string& why) {
  const int S = static_cast<int>(a.stages.size());
  k.assign(S, 0);
  if (S == 0) return true;
  int dwell = 0;
  for (const auto& st : a.stages) dwell += st.dwell;
  const double travel = std::max(0, T - dwell);
  // Latest knot of each stage that leaves room for the later ones (their dwells and `by`
  // windows) before the goal's knot T.
  std::vector<int> latest(S);
  int room = T - 1;
  for (int s = S - 1; s >= 0; --s) {
    latest[s] = room - a.stages[s].dwell;
    if (a.stages[s].by >= 0) latest[s] = std::min(latest[s], a.stages[s].by);
    if (s < static_cast<int>(fixed.size()) && fixed[s] >= 0) latest[s] = std::min(latest[s], fixed[s]);
    room = latest[s] - 1;
  }
  bool ok = true;
  int before = 0, end_prev = 0;
  for (int s = 0; s < S; ++s) {
    const auto& st = a.stages[s];
    int ks = before + static_cast<int>(std::lround(travel * f[s]));
    int lo = std::max({1, st.not_before, end_prev + 1});
    int hi = std::min(latest[s], st.by >= 0 ? st.by : kNoLimit);
    if (s < static_cast<int>(fixed.size()) && fixed[s] >= 0) lo = std::max(lo, fixed[s]), hi = std::min(hi, fixed[s]);
    ks = std::clamp(ks, std::min(lo, hi), hi);
    if (lo > hi) {
      ks = lo;
      if (ok) {
        why = "stage '" + st.name + "' of " + a.name + " cannot be visited at a knot in [" + std::to_string(lo) + ", " +
              std::to_string(hi) + "] (its window, the order of the stages and the goal at T = " + std::to_string(T) +
              ")";
        ok = false;
      }
    }
    k[s] = ks;
    end_prev = ks + st.dwell;
    before += st.dwell;
  }
  return ok;
}

// Every agent placed by its fractions, then the teams: every member at the latest of the knots
// its members chose alone (within all their windows), placed again with that knot fixed.
MissionSchedule place_all(const Problem& problem, int horizon, const std::vector<std::vector<double>>& f) {
  MissionSchedule out;
  out.horizon = horizon;
  const int N = static_cast<int>(problem.agents.size());
  out.visit.resize(N);
  std::vector<std::string> why(N);
  std::vector<bool> ok(N, true);
  for (int i = 0; i < N; ++i) ok[i] = place(problem.agents[i], horizon, f[i], {}, out.visit[i], why[i]);
  struct Team {
    int knot = 0, lo = 1, hi = kNoLimit;
  };
  std::map<std::string, Team> team;
  for (int i = 0; i < N; ++i)
    for (std::size_t s = 0; s < problem.agents[i].stages.size(); ++s)
      if (const auto& st = problem.agents[i].stages[s]; !st.team.empty()) {
        Team& t = team[st.team];
        t.knot = std::max(t.knot, out.visit[i][s]);
        t.lo = std::max(t.lo, st.not_before);
        if (st.by >= 0) t.hi = std::min(t.hi, st.by);
      }
  // A member's own window (a user-fixed knot above all) bounds the common knot: the latest knot
  // alone would otherwise leave that member no knot at all.
  for (auto& [name, t] : team)
    if (t.lo <= t.hi) t.knot = std::clamp(t.knot, t.lo, t.hi);
  if (!team.empty())
    for (int i = 0; i < N; ++i) {
      const auto& a = problem.agents[i];
      std::vector<int> fixed(a.stages.size(), -1);
      bool any = false;
      for (std::size_t s = 0; s < a.stages.size(); ++s)
        if (!a.stages[s].team.empty()) fixed[s] = team[a.stages[s].team].knot, any = true;
      if (!any) continue;
      why[i].clear();
      ok[i] = place(a, horizon, f[i], fixed, out.visit[i], why[i]);
    }
  for (int i = 0; i < N; ++i)
    if (!ok[i] && out.feasible) out.feasible = false, out.why = why[i];
  return out;
}

// How deep agent a's state x lies in stage st's region (no eps): the sound margin of the point.
double depth(const AgentSpec& a, const MissionStage& st, const Eigen::VectorXd& x) {
  Eigen::Vector2d p;
  p = xy_point(a, x.data());
  return stage_margin(st, Box{x, x}, Box{p, p});
}

}  // namespace

std::string stage_name(const AgentSpec& agent, int stage) {
  return "stage " + agent.stages[static_cast<std::size_t>(stage)].name + " of " + agent.name;
}

MissionSchedule schedule_missions(const Problem& problem, int horizon) {
  std::vector<std::vector<double>> f;
  for (const auto& a : problem.agents) f.push_back(straight_fractions(a));
  return place_all(problem, horizon, f);
}

MissionSchedule retime_missions(const Problem& problem, const MissionSchedule& current,
                                const std::vector<Eigen::VectorXd>& x) {
  const int T = static_cast<int>(x.size()) - 1;
  const int N = static_cast<int>(problem.agents.size());
  const ProductLayout at(problem);
  std::vector<std::vector<double>> f(N);
  for (int i = 0; i < N; ++i) {
    const AgentSpec& a = problem.agents[i];
    const int S = static_cast<int>(a.stages.size());
    if (S == 0) continue;
    auto state = [&](int k) -> Eigen::VectorXd { return x[static_cast<std::size_t>(k)].segment(at.state[i], a.n()); };
    std::vector<double> arc(T + 1, 0.0);
    Eigen::Vector2d prev;
    for (int k = 0; k <= T; ++k) {
      Eigen::Vector2d p;
      const Eigen::VectorXd xi = state(k);
      p = xy_point(a, xi.data());
      if (k > 0) arc[k] = arc[k - 1] + (p - prev).norm();
      prev = p;
    }
    const bool known = i < static_cast<int>(current.visit.size()) && static_cast<int>(current.visit[i].size()) == S;
    int dwell = 0;
    for (const auto& st : a.stages) dwell += st.dwell;
    const double travel = std::max(1, T - dwell);
    if (!(arc[T] > 1e-9)) {  // standing still: the path says nothing about the pace
      f[i] = straight_fractions(a);
      if (known)
        for (int s = 0, before = 0; s < S; before += a.stages[s].dwell, ++s)
          f[i][s] = std::clamp((current.visit[i][s] - before) / travel, 0.0, 1.0);
      continue;
    }
    // Deepest pass through each region in order, before the next stage's current knot (a path
    // that passes a region twice, out and back, keeps the pass its plan used); the dwell's knots
    // count by their worst.
    f[i].resize(S);
    int from = 1;
    for (int s = 0; s < S; ++s) {
      const MissionStage& st = a.stages[s];
      const int until = known && s + 1 < S ? current.visit[i][s + 1] - 1 : T;
      int best = std::min(from, T);
      double deepest = -std::numeric_limits<double>::infinity();
      for (int k = from; k + st.dwell <= until; ++k) {
        double d = std::numeric_limits<double>::infinity();
        for (int j = k; j <= k + st.dwell; ++j) d = std::min(d, depth(a, st, state(j)));
        if (d > deepest) deepest = d, best = k;
      }
      f[i][s] = arc[best] / arc[T];
      from = best + st.dwell + 1;
    }
  }
  return place_all(problem, T, f);
}

double fastest_leg_speed(const AgentSpec& a, const std::vector<int>& visits, int horizon, double tau) {
  const int S = static_cast<int>(a.stages.size());
  if (S == 0 || static_cast<int>(visits.size()) != S || !(tau > 0)) return 0.0;
  const Eigen::VectorXd gc = a.goal.center();
  Eigen::Vector2d from = xy_point(a, a.x0.data());
  int since = 0;  // the knot the leg starts at
  double fastest = 0.0;
  for (int s = 0; s <= S; ++s) {
    const Eigen::Vector2d to = s < S ? region_centre(a, a.stages[s]) : xy_point(a, gc.data());
    const int until = s < S ? visits[s] : horizon;
    const double d = (to - from).cwiseAbs().maxCoeff();
    if (until > since && std::isfinite(d)) fastest = std::max(fastest, d / ((until - since) * tau));
    if (s < S) since = visits[s] + a.stages[s].dwell;
    from = to;
  }
  return fastest;
}

std::string schedule_error(const Problem& problem, const MissionSchedule& s, int horizon) {
  const int N = static_cast<int>(problem.agents.size());
  if (static_cast<int>(s.visit.size()) != N) return "the schedule has " + std::to_string(s.visit.size()) + " agents, the problem " + std::to_string(N);
  std::map<std::string, int> team;
  for (int i = 0; i < N; ++i) {
    const AgentSpec& a = problem.agents[i];
    if (s.visit[i].size() != a.stages.size())
      return a.name + " has " + std::to_string(a.stages.size()) + " stages, the schedule " + std::to_string(s.visit[i].size()) + " knots";
    int end_prev = 0;
    for (std::size_t t = 0; t < a.stages.size(); ++t) {
      const MissionStage& st = a.stages[t];
      const int k = s.visit[i][t];
      const std::string at = "stage '" + st.name + "' of " + a.name + ": knot " + std::to_string(k);
      if (k <= end_prev || k < 1) return at + " is not after the previous stage's last dwell knot " + std::to_string(end_prev);
      if (k < st.not_before) return at + " is before not_before " + std::to_string(st.not_before);
      if (st.by >= 0 && k > st.by) return at + " is after by " + std::to_string(st.by);
      end_prev = k + st.dwell;
      if (end_prev > horizon - 1) return at + " with dwell " + std::to_string(st.dwell) + " does not end before T = " + std::to_string(horizon);
      if (!st.team.empty()) {
        const auto [it, fresh] = team.try_emplace(st.team, k);
        if (!fresh && it->second != k) return at + " is not its team '" + st.team + "''s knot " + std::to_string(it->second);
      }
    }
  }
  return {};
}

Problem with_visits(const Problem& problem, const MissionSchedule& s) {
  if (std::all_of(problem.agents.begin(), problem.agents.end(), [](const AgentSpec& a) { return a.stages.empty(); }))
    return problem;
  if (!schedule_error(problem, s, s.horizon).empty()) return problem;
  Problem out = problem;
  for (std::size_t i = 0; i < out.agents.size(); ++i)
    for (std::size_t t = 0; t < out.agents[i].stages.size(); ++t) {
      MissionStage& st = out.agents[i].stages[t];
      st.not_before = st.by = s.visit[i][t];
    }
  return out;
}

MissionSchedule schedule_or_initial(const Problem& problem, const MissionSchedule& s, int horizon) {
  if (!s.empty() && s.horizon == horizon && schedule_error(problem, s, horizon).empty()) return s;
  return schedule_missions(problem, horizon);
}

// Directed rounding from error-free transformations in round-to-nearest (directed_rounding.hpp),
// on plain doubles: the spec monitor asks at every substep, and Boost.Interval's former two mode
// switches per operation were a third of a mission's closed-loop verification.
Box linear_workspace_box(const Workspace& ws, const Box& state) {
  const RoundToNearestScope nearest;
  Box out{Eigen::VectorXd(2), Eigen::VectorXd(2)};
  for (int c = 0; c < 2; ++c) {
    const int at = ws.index[c];
    out.lo[c] = at >= 0 ? fast_detail::add_down(state.lo[at], ws.offset[c]) : ws.offset[c];
    out.hi[c] = at >= 0 ? fast_detail::add_up(state.hi[at], ws.offset[c]) : ws.offset[c];
  }
  return out;
}

double stage_margin(const MissionStage& stage, const Box& state, const Box& workspace) {
  return stage_margin(stage, state.lo.data(), state.hi.data(), workspace.lo.data(), workspace.hi.data());
}

double stage_margin(const MissionStage& stage, const double* state_lo, const double* state_hi, const double* ws_lo,
                    const double* ws_hi) {
  using fast_detail::sub_down;
  const RoundToNearestScope nearest;
  double m = std::numeric_limits<double>::infinity();
  if (!stage.is_polygon()) {
    for (int c = 0; c < stage.box.dim(); ++c) {
      if (!std::isfinite(state_lo[c]) || !std::isfinite(state_hi[c])) return -std::numeric_limits<double>::infinity();
      m = std::min({m, sub_down(state_lo[c], stage.box.lo[c]), sub_down(stage.box.hi[c], state_hi[c])});
    }
    return m;
  }
  // Distance of the box's worst corner to each edge line, inward positive: cross(e, p - v) / |e|
  // for the counter-clockwise polygon, in interval arithmetic over the whole box.
  if (!std::isfinite(ws_lo[0]) || !std::isfinite(ws_hi[0]) || !std::isfinite(ws_lo[1]) || !std::isfinite(ws_hi[1]))
    return -std::numeric_limits<double>::infinity();
  const FastInterval px(ws_lo[0], ws_hi[0]), py(ws_lo[1], ws_hi[1]);
  const std::size_t V = stage.polygon.size();
  for (std::size_t i = 0; i < V; ++i) {
    const auto& v = stage.polygon[i];
    const auto& w = stage.polygon[(i + 1) % V];
    const FastInterval ex = FastInterval(w.x()) - FastInterval(v.x()), ey = FastInterval(w.y()) - FastInterval(v.y());
    const FastInterval len2 = ex * ex + ey * ey;
    const FastInterval len = FastInterval::raw(fast_detail::sqrt_down(std::max(0.0, len2.lower())),
                                               fast_detail::sqrt_up(len2.upper()));
    const FastInterval d = (ex * (py - FastInterval(v.y())) - ey * (px - FastInterval(v.x()))) / len;
    m = std::min(m, d.lower());
  }
  return m;
}

StageConstraint::StageConstraint(std::string name, const AgentSpec& a, int offset, int stage, std::vector<int> steps,
                                 double clearance)
    : name_(std::move(name)), steps_(std::move(steps)) {
  std::sort(steps_.begin(), steps_.end());
  const MissionStage& st = a.stages[static_cast<std::size_t>(stage)];
  if (!st.is_polygon()) {
    for (int c = 0; c < a.n(); ++c) {
      const bool lo = st.box.lo[c] > a.state_bounds.lo[c], hi = st.box.hi[c] < a.state_bounds.hi[c];
      if (!lo && !hi) continue;  // the state bounds already say as much
      const int col = static_cast<int>(support_.size());
      support_.push_back(offset + c);
      const double r = a.tube.eps[c] + clearance;
      if (lo) rows_.push_back({{col, -1}, {-1.0, 0.0}, -(st.box.lo[c] + r)});
      if (hi) rows_.push_back({{col, -1}, {1.0, 0.0}, st.box.hi[c] - r});
    }
    return;
  }
  // Polygon (linear workspace, checked by the loader): p_c = x[index c] + offset c.
  const Workspace& ws = a.workspace;
  int col[2] = {-1, -1};
  for (int c = 0; c < 2; ++c)
    if (ws.index[c] >= 0) col[c] = static_cast<int>(support_.size()), support_.push_back(offset + ws.index[c]);
  const std::size_t V = st.polygon.size();
  for (std::size_t i = 0; i < V; ++i) {
    const auto& v = st.polygon[i];
    const auto& w = st.polygon[(i + 1) % V];
    const Eigen::Vector2d e = w - v;
    const Eigen::Vector2d nrm = Eigen::Vector2d(e.y(), -e.x()) / e.norm();  // outward
    Row row{{col[0], col[1]}, {nrm[0], nrm[1]}, nrm.dot(v) - clearance};
    for (int c = 0; c < 2; ++c) {
      if (col[c] >= 0) row.bound -= std::abs(nrm[c]) * a.tube.eps[ws.index[c]];
      row.bound -= nrm[c] * ws.offset[c];
    }
    rows_.push_back(row);
  }
}

void StageConstraint::evaluate(const double* x, double* g, double* jac) const {
  const int w = static_cast<int>(support_.size());
  for (std::size_t r = 0; r < rows_.size(); ++r) {
    const Row& row = rows_[r];
    double v = -row.bound;
    if (jac)
      for (int j = 0; j < w; ++j) jac[r * w + j] = 0.0;
    for (int t = 0; t < 2; ++t)
      if (row.col[t] >= 0) {
        v += row.a[t] * x[support_[row.col[t]]];
        if (jac) jac[r * w + row.col[t]] = row.a[t];
      }
    g[r] = v;
  }
}

Eigen::VectorXd stage_waypoint(const AgentSpec& a, int s, int offset, int n) {
  Eigen::VectorXd x = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
  const MissionStage& st = a.stages[static_cast<std::size_t>(s)];
  if (st.is_polygon()) {
    const Eigen::Vector2d c = region_centre(a, st);
    for (int j = 0; j < 2; ++j)
      if (a.workspace.index[j] >= 0) x[offset + a.workspace.index[j]] = c[j] - a.workspace.offset[j];
    return x;
  }
  for (int c = 0; c < a.n(); ++c)
    if (st.box.lo[c] > a.state_bounds.lo[c] || st.box.hi[c] < a.state_bounds.hi[c])
      x[offset + c] = 0.5 * (std::max(st.box.lo[c], a.state_bounds.lo[c]) + std::min(st.box.hi[c], a.state_bounds.hi[c]));
  return x;
}

std::vector<StageVisit> stage_visits(const Problem& problem, int horizon) {
  return stage_visits(problem, schedule_missions(problem, horizon));
}

std::vector<StageVisit> stage_visits(const Problem& problem, const MissionSchedule& sched) {
  std::vector<StageVisit> out;
  for (int i = 0; i < static_cast<int>(problem.agents.size()); ++i) {
    const auto& a = problem.agents[i];
    for (int s = 0; s < static_cast<int>(a.stages.size()); ++s) {
      StageVisit v;
      v.agent = i;
      v.stage = s;
      v.name = stage_name(a, s);
      v.step = sched.visit[i][s];
      v.dwell = a.stages[s].dwell;
      out.push_back(v);
    }
  }
  return out;
}

namespace {
bool any_staged(const Problem& problem) {
  return std::any_of(problem.obstacles.begin(), problem.obstacles.end(), [](const Obstacle& o) { return o.staged; });
}
}  // namespace

ObstacleWindows::ObstacleWindows(const Problem& problem, int horizon)
    : ObstacleWindows(problem, horizon > 0 && any_staged(problem) ? schedule_missions(problem, horizon) : MissionSchedule{}) {}

ObstacleWindows::ObstacleWindows(const Problem& problem, const MissionSchedule& visits) {
  const int horizon = visits.horizon;
  const MissionSchedule sched = visits.visit.size() == problem.agents.size() ? visits : schedule_missions(problem, horizon);
  if (!any_staged(problem) || horizon <= 0) return;
  const int N = static_cast<int>(problem.agents.size());
  obstacles_ = static_cast<int>(problem.obstacles.size());
  knots_.assign(static_cast<std::size_t>(N * obstacles_), {});
  for (int i = 0; i < N; ++i) {
    const AgentSpec& a = problem.agents[i];
    for (int o = 0; o < obstacles_; ++o)
      if (problem.obstacles[o].staged) knots_[static_cast<std::size_t>(i * obstacles_ + o)].assign(horizon + 1, 0);
    auto mark = [&](const std::vector<int>& obs, int from, int to) {
      for (int o : obs) {
        if (o < 0 || o >= obstacles_ || !problem.obstacles[o].staged) continue;
        auto& on = knots_[static_cast<std::size_t>(i * obstacles_ + o)];
        for (int k = std::max(0, from); k <= std::min(horizon, to); ++k) on[static_cast<std::size_t>(k)] = 1;
      }
    };
    int start = 0;
    for (int s = 0; s < static_cast<int>(a.stages.size()); ++s) {
      const MissionStage& st = a.stages[s];
      const int end = std::min(horizon, sched.visit[i][s] + st.dwell);
      mark(st.avoid, start, end);
      mark(st.avoid_after, end, horizon);
      start = end;
    }
  }
}

std::vector<int> ObstacleWindows::knots(int agent, int obstacle) const {
  std::vector<int> out;
  if (knots_.empty()) return out;
  const auto& on = knots_[static_cast<std::size_t>(agent * obstacles_ + obstacle)];
  for (std::size_t k = 1; k < on.size(); ++k)
    if (on[k]) out.push_back(static_cast<int>(k));
  return out;
}

std::string ObstacleWindows::describe(int agent, int obstacle) const {
  std::string out;
  if (knots_.empty()) return out;
  const auto& on = knots_[static_cast<std::size_t>(agent * obstacles_ + obstacle)];
  const int T = static_cast<int>(on.size()) - 1;
  for (int k = 0; k <= T; ++k) {
    if (!on[static_cast<std::size_t>(k)]) continue;
    int e = k;
    while (e < T && on[static_cast<std::size_t>(e + 1)]) ++e;
    out += (out.empty() ? "steps " : ", ") + std::to_string(k) + (e > k ? "-" + std::to_string(e) : "");
    k = e;
  }
  return out;
}

}  // namespace marsyn::planning
