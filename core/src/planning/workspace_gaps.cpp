#include "marsyn/core/planning/workspace_gaps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "marsyn/core/planning/geometry.hpp"
#include "marsyn/core/planning/margins.hpp"
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

std::vector<NarrowGap> narrow_gaps(const Problem& problem) {
  std::vector<NarrowGap> out;
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
  auto closed = [&](const std::string& first, const std::string& second, double width, const std::vector<size_t>& who,
                    int axis, int sides) {
    NarrowGap g{first, second, width, 0.0, 0.0, {}, false, axis};
    for (size_t i : who) {
      const double fixed = sides * (delta + problem.agents[i].radius);
      const double need = fixed + 2.0 * tube(i, axis);
      if (width < need) {
        if (need > g.needed) {
          g.fixed = fixed;
          g.body = problem.agents[i].radius > 0;
        }
        g.needed = std::max(g.needed, need);
        g.agents.push_back(problem.agents[i].name);
        g.footprint = g.footprint || !problem.agents[i].workspace.linear();
      }
    }
    if (g.agents.empty()) return;
    // One warning per cause: the agents an edge gap closes, each found on its own, are one gap
    // (a team with the same bounds got one line per robot).
    for (NarrowGap& h : out)
      if (h.first == g.first && h.second == g.second && h.width == g.width && h.axis == g.axis) {
        if (g.needed > h.needed) h.fixed = g.fixed, h.body = g.body, h.needed = g.needed;
        h.agents.insert(h.agents.end(), g.agents.begin(), g.agents.end());
        h.footprint = h.footprint || g.footprint;
        return;
      }
    out.push_back(std::move(g));
  };
  std::vector<size_t> everyone(problem.agents.size());
  for (size_t i = 0; i < everyone.size(); ++i) everyone[i] = i;
  const auto& obs = problem.obstacles;
  // Staged obstacles (scope: stages) are left out: they close a gap only on some stages' way.
  for (size_t p = 0; p < obs.size(); ++p)
    for (size_t q = p + 1; q < obs.size(); ++q) {
      if (obs[p].staged || obs[q].staged) continue;
      const double w = prism_distance(obs[p], obs[q], problem.delta_norm);
      if (w > 0) closed("obstacle " + obs[p].name, "obstacle " + obs[q].name, w, everyone, separating_axis(obs[p], obs[q]), 2);
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
        if (w > 0 && std::isfinite(w)) closed("obstacle " + o.name, e.name, w, {i}, e.axis, 1);
      }
  }
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

double start_eps_factor(const Problem& problem) {
  double f = 1.0;
  for (const auto& c : all_crowded_starts(problem)) f = std::min(f, c.eps_factor);
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
