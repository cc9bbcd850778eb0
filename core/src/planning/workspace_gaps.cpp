#include "marsyn/core/planning/workspace_gaps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <unordered_map>

#include "marsyn/core/planning/geometry.hpp"
#include "marsyn/core/planning/margins.hpp"
#include "marsyn/core/planning/routes.hpp"
#include "marsyn/core/planning/spec_margins.hpp"
#include "marsyn/number_text.hpp"

namespace marsyn::planning {

namespace {

// Distance between two disjoint convex polygons in the given norm: attained at a vertex of one
// of them against the other (the Minkowski difference's edges are the polygons' edges), so the
// exact point-to-polygon distances suffice. 0 when they overlap.
double polygon_distance(const Polygon& a, const Polygon& b, Norm norm) {
  auto d = [&](const Polygon& poly, const Eigen::Vector2d& p) {
    return norm == Norm::Inf ? signed_distance_inf(poly, p) : signed_distance_two(poly, p);
  };
  double out = std::numeric_limits<double>::infinity();
  for (const auto& v : a) out = std::min(out, d(b, v));
  for (const auto& v : b) out = std::min(out, d(a, v));
  return std::max(out, 0.0);
}

// The same between two vertical prisms (3-D workspaces): the prisms' difference is the polygons'
// difference times the height intervals' difference, so the distance combines the polygons'
// distance s and the intervals' gap h >= 0 (max in the inf-norm, hypot in the 2-norm), exactly.
double prism_distance(const Obstacle& a, const Obstacle& b, Norm norm) {
  const double s = polygon_distance(a.vertices, b.vertices, norm);
  const double h = std::max({b.z_lo - a.z_hi, a.z_lo - b.z_hi, 0.0});
  if (h == 0.0) return s;  // the plane's figure, bit for bit
  return norm == Norm::Inf ? std::max(s, h) : std::hypot(s, h);
}

struct Edge {
  std::string name;
  int axis;      // workspace coordinate
  double at;     // the edge's position
  bool low;      // the edge bounds the coordinate from below
};

}  // namespace

// The workspace coordinate along which two obstacles are apart while their extents overlap in
// every other one (beds side by side across x), or -1 (apart diagonally).
int separating_axis(const Obstacle& a, const Obstacle& b) {
  double lo[2][3], hi[2][3];
  const Obstacle* o[2] = {&a, &b};
  for (int k = 0; k < 2; ++k) {
    for (int c = 0; c < 2; ++c) lo[k][c] = std::numeric_limits<double>::infinity(), hi[k][c] = -lo[k][c];
    for (const auto& v : o[k]->vertices)
      for (int c = 0; c < 2; ++c) lo[k][c] = std::min(lo[k][c], v[c]), hi[k][c] = std::max(hi[k][c], v[c]);
    lo[k][2] = o[k]->z_lo, hi[k][2] = o[k]->z_hi;
  }
  int axis = -1;
  for (int c = 0; c < 3; ++c) {
    if (!(lo[1][c] > hi[0][c] || lo[0][c] > hi[1][c])) continue;  // overlapping (or unbounded) along c
    if (axis >= 0) return -1;
    axis = c;
  }
  return axis;
}

namespace {

// One agent a gap is closed to, with what it would need there; narrow_gaps groups them by gap.
struct Closure {
  std::string first, second;
  double width = 0.0;
  int axis = -1;
  Polygon plug;
  std::size_t agent = 0;
  double need = 0.0, fixed = 0.0;
  bool body = false, footprint = false;
};

// The region a gap spans in the plane, what a route through it crosses: the two obstacles' convex
// hull (the obstacles and the band between them), or an obstacle with its shadow on the edge.
// Empty across z, where a plane's route cannot tell.
Polygon plug_between(const Obstacle& a, const Obstacle& b) {
  std::vector<Eigen::Vector2d> pts(a.vertices.begin(), a.vertices.end());
  pts.insert(pts.end(), b.vertices.begin(), b.vertices.end());
  return convex_hull(std::move(pts));
}

Polygon plug_to_edge(const Obstacle& o, int axis, double at) {
  std::vector<Eigen::Vector2d> pts(o.vertices.begin(), o.vertices.end());
  for (const auto& v : o.vertices) {
    Eigen::Vector2d s = v;
    s[axis] = at;
    pts.push_back(s);
  }
  return convex_hull(std::move(pts));
}

std::vector<Closure> closures(const Problem& problem) {
  std::vector<Closure> out;
  const bool inf = problem.delta_norm == Norm::Inf;
  const double delta = problem.obstacle_delta();
  std::vector<WorkspaceMargin> margin(problem.agents.size());
  for (size_t i = 0; i < problem.agents.size(); ++i) {
    const auto& a = problem.agents[i];
    margin[i] = global_margin(a, a.state_bounds.shrunk(a.tube.eps), 16);
  }
  // The tube's share of a gap across `axis` (its margin in that coordinate; the largest one for
  // a slanted gap), on each side.
  auto tube = [&](size_t i, int axis) {
    const WorkspaceMargin& m = margin[i];
    return axis == 0 ? m.x : axis == 1 ? m.y : axis == 2 ? m.z : inf ? m.inf() : m.two();
  };
  // sides: how many clearances the gap holds besides the tubes (2 between obstacles, 1 at a
  // workspace edge, whose bounds already hold the body); each is delta plus the agent's radius,
  // what no tube changes.
  // The names and the plug are made only for a gap closed to someone: a field of 1000 robots
  // among pillars has half a million pairs of them, nearly all open.
  auto closed = [&](const auto& make, double width, size_t i, int axis, int sides) {
    const double fixed = sides * (delta + problem.agents[i].radius);
    const double need = fixed + 2.0 * tube(i, axis);
    if (!(width < need)) return;
    Closure c = make();
    c.width = width, c.axis = axis, c.agent = i, c.need = need, c.fixed = fixed;
    c.body = problem.agents[i].radius > 0, c.footprint = !problem.agents[i].workspace.linear();
    out.push_back(std::move(c));
  };
  const auto& obs = problem.obstacles;
  // Staged obstacles (scope: stages) are left out: they close a gap only on some stages' way.
  for (size_t p = 0; p < obs.size(); ++p)
    for (size_t q = p + 1; q < obs.size(); ++q) {
      if (obs[p].staged || obs[q].staged) continue;
      const double w = prism_distance(obs[p], obs[q], problem.delta_norm);
      if (!(w > 0)) continue;
      const int axis = separating_axis(obs[p], obs[q]);
      std::optional<Closure> made;
      auto make = [&] {
        if (!made) {
          made.emplace();
          made->first = "obstacle " + obs[p].name, made->second = "obstacle " + obs[q].name;
          if (axis != 2 && polygon_distance(obs[p].vertices, obs[q].vertices, problem.delta_norm) == w)
            made->plug = plug_between(obs[p], obs[q]);
        }
        return *made;
      };
      for (size_t i = 0; i < problem.agents.size(); ++i) closed(make, w, i, axis, 2);
    }
  // An obstacle near the edge of an agent's workspace (a linear workspace: its state bounds).
  for (size_t i = 0; i < problem.agents.size(); ++i) {
    const auto& a = problem.agents[i];
    if (!a.workspace.linear()) continue;
    std::vector<Edge> edges;
    for (int c = 0; c < a.workspace.dim(); ++c) {
      const int at = a.workspace.index[c];
      if (at < 0) continue;
      const double off = a.workspace.offset[c];
      const char* axis = c == 0 ? "x" : c == 1 ? "y" : "z";
      if (std::isfinite(a.state_bounds.lo[at]))
        edges.push_back({std::string("the edge ") + axis + " = " + number_text(a.state_bounds.lo[at] + off) +
                             " of the workspace",
                         c, a.state_bounds.lo[at] + off, true});
      if (std::isfinite(a.state_bounds.hi[at]))
        edges.push_back({std::string("the edge ") + axis + " = " + number_text(a.state_bounds.hi[at] + off) +
                             " of the workspace",
                         c, a.state_bounds.hi[at] + off, false});
    }
    for (const auto& o : obs)
      for (const auto& e : edges) {
        if (o.staged) continue;
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        if (e.axis == 2) {
          lo = o.z_lo, hi = o.z_hi;  // a floor or a ceiling
        } else {
          for (const auto& v : o.vertices) lo = std::min(lo, v[e.axis]), hi = std::max(hi, v[e.axis]);
        }
        const double w = e.low ? lo - e.at : e.at - hi;
        if (w > 0 && std::isfinite(w))
          closed(
              [&] {
                Closure c;
                c.first = "obstacle " + o.name, c.second = e.name;
                if (e.axis != 2) c.plug = plug_to_edge(o, e.axis, e.at);
                return c;
              },
              w, i, e.axis, 1);
      }
  }
  return out;
}

// One warning per cause: the agents a gap closes, each found on its own, are one gap (a team
// with the same bounds got one line per robot).
std::vector<NarrowGap> grouped(const Problem& problem, const std::vector<Closure>& closures) {
  std::vector<NarrowGap> out;
  for (const Closure& c : closures) {
    NarrowGap* g = nullptr;
    for (NarrowGap& h : out)
      if (h.first == c.first && h.second == c.second && h.width == c.width && h.axis == c.axis) g = &h;
    if (!g) {
      out.push_back(NarrowGap{c.first, c.second, c.width, 0.0, 0.0, {}, false, c.axis});
      g = &out.back();
    }
    if (c.need > g->needed) g->fixed = c.fixed, g->body = c.body, g->needed = c.need;
    g->agents.push_back(problem.agents[c.agent].name);
    g->footprint = g->footprint || c.footprint;
  }
  return out;
}

}  // namespace

std::vector<NarrowGap> narrow_gaps(const Problem& problem) {
  return grouped(problem, closures(problem));
}

std::vector<Eigen::Vector2d> way_points(const AgentSpec& a) {
  const Workspace& ws = a.workspace;
  if (!ws.linear() || ws.dim() < 2 || ws.index[0] < 0 || ws.index[1] < 0 || a.x0.size() != a.n()) return {};
  const int ix = ws.index[0], iy = ws.index[1];
  auto centre = [&](const Box& b) {
    return Eigen::Vector2d(0.5 * (b.lo[ix] + b.hi[ix]) + ws.offset[0], 0.5 * (b.lo[iy] + b.hi[iy]) + ws.offset[1]);
  };
  std::vector<Eigen::Vector2d> way{Eigen::Vector2d(a.x0[ix] + ws.offset[0], a.x0[iy] + ws.offset[1])};
  for (const auto& st : a.stages) {
    if (st.is_polygon()) {
      Eigen::Vector2d c = Eigen::Vector2d::Zero();
      for (const auto& v : st.polygon) c += v;
      way.push_back(c / static_cast<double>(st.polygon.size()));
    } else {
      way.push_back(centre(st.box));
    }
  }
  way.push_back(centre(a.goal));
  for (const auto& p : way)
    if (!p.allFinite()) return {};
  return way;
}

namespace {

// The outside of an agent's position bounds as four slabs (the route keeps inside them), out to
// a frame past everything else on the way.
std::vector<Polygon> outside_of(const AgentSpec& a, const std::vector<Polygon>& polygons,
                                const std::vector<Eigen::Vector2d>& way) {
  const Workspace& ws = a.workspace;
  Eigen::Vector2d lo = way[0], hi = way[0];
  auto take = [&](const Eigen::Vector2d& p) { lo = lo.cwiseMin(p), hi = hi.cwiseMax(p); };
  for (const auto& p : way) take(p);
  for (const auto& poly : polygons)
    for (const auto& v : poly) take(v);
  Eigen::Vector2d blo, bhi;
  for (int c = 0; c < 2; ++c) {
    blo[c] = a.state_bounds.lo[ws.index[c]] + ws.offset[c];
    bhi[c] = a.state_bounds.hi[ws.index[c]] + ws.offset[c];
    if (std::isfinite(blo[c])) lo[c] = std::min(lo[c], blo[c]);
    if (std::isfinite(bhi[c])) hi[c] = std::max(hi[c], bhi[c]);
  }
  const Eigen::Vector2d pad = Eigen::Vector2d::Constant(1.0 + (hi - lo).maxCoeff());
  const Eigen::Vector2d flo = lo - pad, fhi = hi + pad;
  auto box = [](double x0, double y0, double x1, double y1) {
    return Polygon{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  };
  std::vector<Polygon> out;
  if (std::isfinite(blo.x())) out.push_back(box(flo.x(), flo.y(), blo.x(), fhi.y()));
  if (std::isfinite(bhi.x())) out.push_back(box(bhi.x(), flo.y(), fhi.x(), fhi.y()));
  if (std::isfinite(blo.y())) out.push_back(box(flo.x(), flo.y(), fhi.x(), blo.y()));
  if (std::isfinite(bhi.y())) out.push_back(box(flo.x(), bhi.y(), fhi.x(), fhi.y()));
  return out;
}

// The length of the shortest way through `way`'s points around the polygons; infinite when a
// leg has none (or a point lies inside one).
double way_length(const std::vector<Polygon>& polygons, const std::vector<Eigen::Vector2d>& way) {
  double length = 0.0;
  for (std::size_t k = 0; k + 1 < way.size(); ++k) {
    bool found = false;
    auto corners = shortest_route(polygons, way[k], way[k + 1], &found);
    if (!found) return std::numeric_limits<double>::infinity();
    corners.push_back(way[k + 1]);
    Eigen::Vector2d at = way[k];
    for (const auto& c : corners) length += (c - at).norm(), at = c;
  }
  return length;
}

bool longer(double a, double b) { return a > b + 1e-9 * (1.0 + b); }

}  // namespace

std::vector<NarrowGap> gaps_on_the_way(const Problem& problem, std::size_t* off_the_way) {
  const std::vector<Closure> all = closures(problem);
  std::vector<bool> keep(all.size(), true);
  std::vector<Polygon> obstacles;
  double vertices = 0;
  for (const auto& o : problem.obstacles)
    if (!o.staged) obstacles.push_back(o.vertices), vertices += static_cast<double>(o.vertices.size());
  // A visibility graph costs about vertices^2 x polygons segment tests a leg; past a budget over
  // all the routes (hundreds of robots among hundreds of pillars) every closed gap is named.
  double work = 0;
  for (const Closure& c : all) {
    const double v = vertices + 16 + 2.0 * static_cast<double>(c.plug.size());
    work += 4.0 * v * v * static_cast<double>(obstacles.size() + 6) *
            (1.0 + static_cast<double>(problem.agents[c.agent].stages.size()));
  }
  std::vector<std::vector<std::size_t>> by_agent(problem.agents.size());
  for (std::size_t k = 0; k < all.size(); ++k)
    if (!all[k].plug.empty()) by_agent[all[k].agent].push_back(k);
  if (problem.workspace_dim == 2 && work <= 4e8)
    for (std::size_t i = 0; i < problem.agents.size(); ++i) {
      const std::vector<std::size_t>& mine = by_agent[i];
      const auto way = way_points(problem.agents[i]);
      if (mine.empty() || way.empty()) continue;
      std::vector<Polygon> base = obstacles;
      for (auto& p : outside_of(problem.agents[i], obstacles, way)) base.push_back(std::move(p));
      // Routes may run along an edge (touching is not crossing): polygons that share one (a wall
      // of boxes, an obstacle on the bounds, a plug beside its edge) would leave a seam of width
      // 0 to pass through. Grown by a hair they overlap; a gap is far wider.
      double span = 0;
      for (const auto& p : way) span = std::max(span, p.cwiseAbs().maxCoeff());
      for (const auto& poly : base)
        for (const auto& v : poly) span = std::max(span, v.cwiseAbs().maxCoeff());
      const double hair = 1e-7 * (1.0 + span);
      for (auto& poly : base) poly = grow_by_box(poly, hair, hair);
      std::vector<Polygon> plugs;
      for (std::size_t k : mine) plugs.push_back(grow_by_box(all[k].plug, hair, hair));
      // The way's length with the plugs of the gaps `plugged(j)` says (j indexes mine).
      auto way_with = [&](const auto& plugged) {
        std::vector<Polygon> polygons = base;
        for (std::size_t j = 0; j < plugs.size(); ++j)
          if (plugged(j)) polygons.push_back(plugs[j]);
        return way_length(polygons, way);
      };
      const double open = way_length(base, way);
      if (!std::isfinite(open)) continue;  // no way even with every gap open: each may be why
      const double closed = way_with([](std::size_t) { return true; });
      // A gap the way needs: the shortest way goes through it (plugging it alone lengthens the
      // way), or every way is closed and opening it alone would give one (doorways side by side).
      for (std::size_t j = 0; j < mine.size(); ++j) {
        const bool through = longer(way_with([&](std::size_t g) { return g == j; }), open);
        const bool only_opening =
            !std::isfinite(closed) && std::isfinite(way_with([&](std::size_t g) { return g != j; }));
        keep[mine[j]] = longer(closed, open) && (through || only_opening);
      }
    }
  std::vector<Closure> needed;
  for (std::size_t k = 0; k < all.size(); ++k)
    if (keep[k]) needed.push_back(all[k]);
  auto out = grouped(problem, needed);
  if (off_the_way) *off_the_way = grouped(problem, all).size() - out.size();
  return out;
}

double gap_eps_factor(const Problem& problem, const RobustCheck& check) {
  const int agent = check.worst_agents[0];
  if (check.passed || agent < 0 || check.worst_agents[1] >= 0) return 1.0;
  const AgentSpec& a = problem.agents[static_cast<std::size_t>(agent)];
  // The obstacle whose requirement (obstacle_name, the check's own name) is the worst.
  std::string side;
  for (std::size_t o = 0; o < problem.obstacles.size() && side.empty(); ++o) {
    const std::string name = obstacle_name(problem, static_cast<int>(o), a);
    if (check.worst.compare(0, name.size(), name) == 0 && (check.worst.size() == name.size() || check.worst[name.size()] == ' '))
      side = "obstacle " + problem.obstacles[o].name;  // as the gaps name it
  }
  if (side.empty()) return 1.0;
  const std::string& who = a.name;
  double f = 1.0;
  for (const auto& g : narrow_gaps(problem)) {
    if ((g.first != side && g.second != side) || std::find(g.agents.begin(), g.agents.end(), who) == g.agents.end())
      continue;
    const double tubes = g.needed - g.fixed;  // the largest agent's tubes among those it closes
    if (!(tubes > 0)) continue;
    f = std::min(f, 0.95 * (g.width - g.fixed) / tubes);
  }
  return f;
}

std::string describe(const NarrowGap& g) {
  std::ostringstream os;
  os.precision(kMessageDigits);
  const char* axis = g.axis == 0 ? "x" : g.axis == 1 ? "y" : g.axis == 2 ? "z" : nullptr;
  const bool edge = g.second.rfind("the edge ", 0) == 0;
  const std::string tube = g.footprint ? std::string("how far the footprint moves inside its eps-tube") + (axis ? std::string(" in ") + axis : "")
                           : axis ? std::string("eps in ") + axis : std::string("eps");
  os << g.first << " and " << g.second << " leave a gap " << g.width << " wide" << (axis ? std::string(" across ") + axis : "");
  const std::string fixed = g.body ? "delta + radius" : "delta";
  os << "; passing it needs " << g.needed << (edge ? " (" + fixed + " + 2 " + tube + ")" : " (2 (" + fixed + " + " + tube + "))")
     << ": closed to ";
  // A field of hundreds names a few and counts the rest.
  constexpr size_t kNamed = 5;
  const size_t named = g.agents.size() > kNamed + 1 ? kNamed : g.agents.size();
  for (size_t i = 0; i < named; ++i) os << (i ? ", " : "") << g.agents[i];
  if (named < g.agents.size()) os << " and " << g.agents.size() - named << " more agents";
  os << " at every horizon";
  return os.str();
}

namespace {

std::vector<CrowdedStart> all_crowded_starts(const Problem& problem) {
  std::vector<CrowdedStart> out;
  const std::size_t n = problem.agents.size();
  std::vector<Point> p(n);
  std::vector<WorkspaceMargin> m(n);
  for (std::size_t i = 0; i < n; ++i) {
    const AgentSpec& a = problem.agents[i];
    if (a.x0.size() != a.n()) return out;
    workspace_point3(*a.dynamics, a.workspace, a.x0.data(), p[i].data());
    m[i] = margin_at(a, a.x0);
  }
  const bool inf = problem.delta_norm == Norm::Inf;
  // Real margin g0 (tubes of width 0) and robust margin g1: the tubes take g0 - g1, so eps x f
  // leaves g0 - f (g0 - g1), zero at f = g0 / (g0 - g1).
  auto crowded = [&](std::string first, std::string second, double g0, double g1, double distance) {
    if (!(g1 < 0)) return;
    CrowdedStart c{std::move(first), std::move(second), distance, distance - g1, 0.0};
    c.eps_factor = g0 > 0 ? g0 / (g0 - g1) : 0.0;
    out.push_back(std::move(c));
  };
  const ObstacleWindows windows(problem, problem.horizon);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t o = 0; o < problem.obstacles.size(); ++o) {
      if (!windows.binds(static_cast<int>(i), static_cast<int>(o), {0, false})) continue;
      const Obstacle& poly = problem.obstacles[o];
      const double clearance = problem.obstacle_clearance(static_cast<int>(i));
      const double g0 = obstacle_margin(poly, p[i], {}, clearance, problem.delta_norm);
      const double g1 = obstacle_margin(poly, p[i], m[i], clearance, problem.delta_norm);
      crowded(problem.agents[i].name, "obstacle " + problem.obstacles[o].name, g0, g1, g0 + clearance);
    }
  if (problem.pairwise_collision)
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        const double clearance = problem.pair_clearance(static_cast<int>(i), static_cast<int>(j));
        const double g0 = collision_margin(p[i], {}, p[j], {}, clearance, problem.delta_norm);
        // A cheap reject first: teams of hundreds have tens of thousands of pairs.
        if (g0 > 2 * ((inf ? m[i].inf() : m[i].two()) + (inf ? m[j].inf() : m[j].two()))) continue;
        const double g1 = collision_margin(p[i], m[i], p[j], m[j], clearance, problem.delta_norm);
        crowded(problem.agents[i].name, problem.agents[j].name, g0, g1, g0 + clearance);
      }
  // A formation pair whose starts keep the tolerance but not with the tubes around them: g0 > 0
  // (the loader refuses a start outside lambda +- mu), the slack affine in the eps factor.
  for (const auto& f : problem.formation) {
    const double g0 = formation_margin(p[f.i], {}, p[f.j], {}, f.lambda, f.mu);
    const double g1 = formation_margin(p[f.i], m[f.i], p[f.j], m[f.j], f.lambda, f.mu);
    if (!(g1 < 0)) continue;
    const double d = (p[f.i] - p[f.j]).norm();
    CrowdedStart c{problem.agents[f.i].name, problem.agents[f.j].name, d, d - g1, g0 > 0 ? g0 / (g0 - g1) : 0.0};
    c.formation = true;
    c.lambda = f.lambda;
    c.mu = f.mu;
    c.robust_mu = f.mu - (g0 - g1);
    out.push_back(std::move(c));
  }
  std::sort(out.begin(), out.end(), [](const CrowdedStart& a, const CrowdedStart& b) {
    return a.distance - a.needed < b.distance - b.needed;
  });
  return out;
}

}  // namespace

std::vector<CrowdedStart> crowded_starts(const Problem& problem, std::size_t limit, std::size_t* total) {
  auto out = all_crowded_starts(problem);
  if (total) *total = out.size();
  if (out.size() > limit) out.resize(limit);
  return out;
}

std::vector<double> start_eps_factors(const Problem& problem) {
  std::vector<double> f(problem.agents.size(), 1.0);
  std::unordered_map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < problem.agents.size(); ++i) index.emplace(problem.agents[i].name, i);
  for (const auto& c : all_crowded_starts(problem))
    for (const std::string* name : {&c.first, &c.second})
      if (const auto at = index.find(*name); at != index.end()) f[at->second] = std::min(f[at->second], c.eps_factor);
  return f;
}

double start_eps_factor(const Problem& problem) {
  double f = 1.0;
  for (double g : start_eps_factors(problem)) f = std::min(f, g);
  return f;
}

double position_eps(const AgentSpec& a) {
  if (!a.workspace.linear()) return -1;
  double e = 0;
  for (int i : a.workspace.index)
    if (i >= 0 && i < a.tube.eps.size()) e = std::max(e, a.tube.eps[i]);
  return e;
}

double formation_eps_factor(const Problem& problem) {
  double f = 1.0;
  for (const auto& p : problem.formation) {
    const AgentSpec &a = problem.agents[p.i], &b = problem.agents[p.j];
    if (!a.workspace.linear() || !b.workspace.linear()) continue;
    // |eps box|_2 over the workspace's coordinates: sqrt(2) in the plane, sqrt(3) in space.
    const double change = std::sqrt(static_cast<double>(a.workspace.dim())) * (position_eps(a) + position_eps(b));
    if (change >= p.mu && change > 0) f = std::min(f, 0.7 * p.mu / change);
  }
  return f;
}

std::string describe(const CrowdedStart& c, const Problem& problem) {
  std::ostringstream os;
  os.precision(kMessageDigits);
  if (c.formation) {
    os << c.first << " and " << c.second << " start " << c.distance << " apart (Euclidean); their formation keeps "
       << c.lambda << " +- " << c.mu << ", with the tubes around them " << c.lambda << " +- " << std::max(c.robust_mu, 0.0)
       << " at every step, step 0 included: no horizon can help; ";
    if (c.eps_factor > 0)
      os << "eps x " << std::floor(c.eps_factor * 100) / 100 << " or less (or starts nearer " << c.lambda << " apart) would make step 0 eps-robust";
    else
      os << "only starts nearer " << c.lambda << " apart would make step 0 eps-robust";
    return os.str();
  }
  const std::string norm = problem.delta_norm == Norm::Inf ? "inf-norm" : "Euclidean";
  os << c.first << (c.second.rfind("obstacle ", 0) == 0 ? " starts " : " and " + c.second + " start ") << c.distance
     << (c.second.rfind("obstacle ", 0) == 0 ? " from " + c.second : std::string(" apart")) << " (" << norm
     << "); the eps-robust plan keeps " << c.needed
     << " (delta and the tubes) at every step, step 0 included: no horizon can help; ";
  if (c.eps_factor > 0)
    os << "eps x " << std::floor(c.eps_factor * 100) / 100 << " or less (or starts further apart) would make step 0 eps-robust";
  else
    os << "only starts further apart would make step 0 eps-robust";
  return os.str();
}

}  // namespace marsyn::planning
