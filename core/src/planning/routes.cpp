#include "marsyn/core/planning/routes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "marsyn/core/planning/margins.hpp"

namespace marsyn::planning {

namespace {

// One leg of an agent's way: from a workspace point at knot k0 to one at knot k1, among the
// obstacles that bind the agent on it (staged ones only on the legs that name them).
struct Leg {
  Eigen::Vector3d from, to;
  int k0, k1;
  std::vector<int> obstacles;
};

// The workspace point of a stage's region: its waypoint (stage_waypoint: the centre in the
// coordinates the region fixes) where it fixes one, `prev`'s elsewhere (a stage that fixes only
// the height keeps the way's x and y).
Eigen::Vector3d stage_point(const AgentSpec& a, int s, const Eigen::Vector3d& prev) {
  const Eigen::VectorXd w = stage_waypoint(a, s, 0, a.n());
  Eigen::Vector3d p = prev;
  for (int c = 0; c < a.workspace.dim(); ++c) {
    const double v = w[a.workspace.index[c]];
    if (std::isfinite(v)) p[c] = v + a.workspace.offset[c];
  }
  return p;
}

bool binds(const AgentSpec& a, const Obstacle& o, int index, std::size_t leg) {
  if (!o.staged) return true;
  auto has = [index](const std::vector<int>& v) { return std::find(v.begin(), v.end(), index) != v.end(); };
  if (leg < a.stages.size() && has(a.stages[leg].avoid)) return true;
  for (std::size_t j = 0; j < leg && j < a.stages.size(); ++j)
    if (has(a.stages[j].avoid_after)) return true;
  return false;
}

// The legs of agent i: start to goal, or through its stages' regions at their knots in `visits`.
std::vector<Leg> legs_of(const Problem& problem, int i, const MissionSchedule& visits, int horizon) {
  const AgentSpec& a = problem.agents[static_cast<std::size_t>(i)];
  const auto& ws = a.workspace;
  const int dim = ws.dim();
  auto centre = [&](int c) {
    const double lo = a.goal.lo[c], hi = a.goal.hi[c];
    return std::isfinite(lo) && std::isfinite(hi) ? 0.5 * (lo + hi) : a.x0[c];
  };
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), goal = Eigen::Vector3d::Zero();
  for (int c = 0; c < dim; ++c) {
    from[c] = a.x0[ws.index[c]] + ws.offset[c];
    goal[c] = centre(ws.index[c]) + ws.offset[c];
  }
  const bool staged = !a.stages.empty() && static_cast<std::size_t>(i) < visits.visit.size() &&
                      visits.visit[static_cast<std::size_t>(i)].size() == a.stages.size();
  std::vector<Leg> legs;
  int k0 = 0;
  for (std::size_t s = 0; staged && s < a.stages.size(); ++s) {
    const int k = visits.visit[static_cast<std::size_t>(i)][s];
    const Eigen::Vector3d p = stage_point(a, static_cast<int>(s), from);
    legs.push_back({from, p, k0, k, {}});
    from = p;
    k0 = std::min(k + a.stages[s].dwell, horizon);
  }
  legs.push_back({from, goal, k0, horizon, {}});
  for (std::size_t l = 0; l < legs.size(); ++l)
    for (std::size_t o = 0; o < problem.obstacles.size(); ++o)
      if (binds(a, problem.obstacles[o], static_cast<int>(o), staged ? l : a.stages.size()))
        legs[l].obstacles.push_back(static_cast<int>(o));
  return legs;
}

// The plane outside the box [lo, hi] as four convex polygons (counter-clockwise), each side only
// where its bound is finite; the box is widened to hold both ends (an end at the bounds keeps its
// route). Far enough out that nothing is routed around them.
std::vector<Polygon> outside_of(Eigen::Vector2d lo, Eigen::Vector2d hi, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  std::vector<Polygon> out;
  for (int c = 0; c < 2; ++c) {
    lo[c] = std::min({lo[c], a[c] - 1e-9, b[c] - 1e-9});
    hi[c] = std::max({hi[c], a[c] + 1e-9, b[c] + 1e-9});
  }
  if (!(lo.array() <= hi.array()).all()) return out;
  double reach = 1.0 + (a - b).norm();
  for (int c = 0; c < 2; ++c)
    if (std::isfinite(hi[c] - lo[c])) reach += hi[c] - lo[c];
  const double L = 10.0 * reach;
  auto at = [](double v, double fallback) { return std::isfinite(v) ? v : fallback; };
  const double x0 = at(lo.x(), a.x() - L), x1 = at(hi.x(), a.x() + L), y0 = at(lo.y(), a.y() - L), y1 = at(hi.y(), a.y() + L);
  auto rect = [](double u0, double v0, double u1, double v1) {
    return Polygon{{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}};
  };
  if (std::isfinite(lo.x())) out.push_back(rect(x0 - L, y0 - L, x0, y1 + L));
  if (std::isfinite(hi.x())) out.push_back(rect(x1, y0 - L, x1 + L, y1 + L));
  if (std::isfinite(lo.y())) out.push_back(rect(x0 - L, y0 - L, x1 + L, y0));
  if (std::isfinite(hi.y())) out.push_back(rect(x0 - L, y1, x1 + L, y1 + L));
  return out;
}

}  // namespace

std::vector<Waypoint> route_waypoints(const Problem& problem, int horizon, const MissionSchedule& schedule,
                                      const std::vector<int>& other_side) {
  std::vector<Waypoint> out;
  if (problem.obstacles.empty() || horizon < 2) return out;
  const ProductLayout layout(problem);
  const int n = layout.state_dim();
  const bool inf = problem.delta_norm == Norm::Inf;
  const MissionSchedule visits = schedule_or_initial(problem, schedule, horizon);
  for (size_t i = 0; i < problem.agents.size(); ++i) {
    const AgentSpec& a = problem.agents[i];
    const auto& ws = a.workspace;
    if (!ws.linear() || ws.index[0] < 0 || ws.index[1] < 0) continue;
    const int dim = ws.dim();
    if (dim == 3 && ws.index[2] < 0) continue;
    // What the plan keeps from an obstacle (the obstacle constraint's growth), and 10% more.
    const WorkspaceMargin m = global_margin(a, a.state_bounds.shrunk(a.tube.eps), 16);
    const Eigen::Vector3d g = 1.1 * (Eigen::Vector3d::Constant(problem.obstacle_clearance(static_cast<int>(i))) +
                                     (inf ? Eigen::Vector3d(m.x, m.y, m.z) : Eigen::Vector3d::Constant(m.two())));
    // The position bounds the robust plan keeps (less the margin, and 10% of it more): routes
    // stay inside them (a serpentine's walls reach the bounds; a route around their ends outside
    // the hall is no route).
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity()), hi = -lo;
    for (int c = 0; c < dim; ++c) {
      const int s = ws.index[c];
      const double keep = 1.1 * (c == 0 ? m.x : c == 1 ? m.y : m.z);
      lo[c] = a.state_bounds.lo[s] + ws.offset[c] + keep;
      hi[c] = a.state_bounds.hi[s] + ws.offset[c] - keep;
    }
    const bool flip = std::find(other_side.begin(), other_side.end(), static_cast<int>(i)) != other_side.end();
    for (const Leg& leg : legs_of(problem, static_cast<int>(i), visits, horizon)) {
      if (leg.k1 - leg.k0 < 2) continue;  // no knot between the ends to hold a corner
      std::vector<Prism> grown;
      for (int o : leg.obstacles) {
        const Obstacle& ob = problem.obstacles[static_cast<std::size_t>(o)];
        grown.push_back({grow_by_box(ob.vertices, g.x(), g.y()),
                         dim == 2 ? -std::numeric_limits<double>::infinity() : ob.z_lo - g.z(),
                         dim == 2 ? std::numeric_limits<double>::infinity() : ob.z_hi + g.z()});
      }
      const Eigen::Vector3d &from = leg.from, &to = leg.to;
      auto route = [&](const std::vector<Prism>& prisms, bool* found) {
        std::vector<Eigen::Vector3d> corners;
        if (dim == 3) return route_in_space(prisms, lo, hi, from, to, found);
        std::vector<Polygon> polygons;
        for (const auto& p : prisms) polygons.push_back(p.base);
        for (const auto& frame : outside_of(lo.head<2>(), hi.head<2>(), from.head<2>(), to.head<2>()))
          polygons.push_back(frame);
        for (const auto& c : shortest_route(polygons, from.head<2>(), to.head<2>(), found))
          corners.push_back(Eigen::Vector3d(c.x(), c.y(), 0.0));
        return corners;
      };
      std::vector<Eigen::Vector3d> corners = route(grown, nullptr);
      if (!corners.empty() && flip) {
        // Far past the bounds (or everything, where they are open), so the wall cannot be walked around inside them.
        Eigen::Vector3d span = (to - from).cwiseAbs();
        for (int c = 0; c < dim; ++c)
          if (std::isfinite(hi[c] - lo[c])) span[c] = std::max(span[c], hi[c] - lo[c]);
        for (const auto& p : grown)
          for (const auto& v : p.base) span.head<2>() = span.head<2>().cwiseMax((v - from.head<2>()).cwiseAbs());
        if (const auto wall = other_side_barrier(grown, from, to, corners, 10.0 * (1.0 + span.norm()))) {
          std::vector<Prism> walled = grown;
          walled.push_back(*wall);
          bool found = false;
          const auto other = route(walled, &found);
          const bool inside = std::all_of(other.begin(), other.end(), [&](const Eigen::Vector3d& p) {
            return (p.array() >= lo.array() - 1e-9).all() && (p.array() <= hi.array() + 1e-9).all();
          });
          if (found && !other.empty() && inside) corners = other;
        }
      }
      if (corners.empty()) continue;
      std::vector<double> along{0.0};
      Eigen::Vector3d prev = from;
      for (const auto& c : corners) along.push_back(along.back() + (c - prev).norm()), prev = c;
      const double total = along.back() + (to - prev).norm();
      const int span = leg.k1 - leg.k0;
      for (size_t j = 0; j < corners.size(); ++j) {
        Waypoint w;
        w.step = leg.k0 + std::clamp(static_cast<int>(std::lround(span * along[j + 1] / total)), 1, span - 1);
        w.x = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
        // Weakly held, a reference through the corners is undone by the first steps of a solver
        // started at rest (the obstacle field of tests/continuous: 40 x holds the route, 1 x and
        // 10 x did not).
        w.follow = 40.0;
        for (int c = 0; c < dim; ++c) w.x[layout.state[i] + ws.index[c]] = corners[j][c] - ws.offset[c];
        out.push_back(std::move(w));
      }
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const Waypoint& p, const Waypoint& q) { return p.step < q.step; });
  return out;
}

}  // namespace marsyn::planning
