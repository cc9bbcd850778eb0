#include "scene_fields.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "agent_fields.hpp"
#include "field_text.hpp"
#include "marsyn/core/problem/input_limits.hpp"
#include "marsyn/core/planning/spec_margins.hpp"
#include "plugin_fields.hpp"

namespace marsyn::loader {

// A workspace point as a message prints it: a coordinate within rounding of 0 beside the point's
// size (cos(pi/2) = 6.1e-17 for a footprint's offset) is 0, not rounding noise.
std::string point(const planning::Point& p, int dim) {
  Eigen::VectorXd v = dim == 3 ? Eigen::VectorXd(p) : Eigen::VectorXd(Eigen::Vector2d(p.x(), p.y()));
  const double scale = std::max(1.0, v.cwiseAbs().maxCoeff());
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (std::abs(v[i]) < 1e-12 * scale) v[i] = 0;
  return list_text(v);
}

// The real specification at k = 0, with the exact geometry of the robustness check
// (planning/spec_margins.hpp): each agent's workspace point at x0 keeps delta from every obstacle and
// from every other agent. A start violating it can never be planned for.
void check_start_geometry(const Problem& pb, const std::vector<Field>& x0_fields) {
  const bool inf = pb.delta_norm == Norm::Inf;
  const std::string norm = inf ? "inf-norm" : "Euclidean";
  const int N = static_cast<int>(pb.agents.size()), B = pb.body_count();
  std::vector<planning::Point> p(static_cast<std::size_t>(B));
  const int D = pb.workspace_dim;
  auto point = [D](const planning::Point& q) { return loader::point(q, D); };
  // Every body (slot b: planning::body_points), named as the agent's point or as "a's cart".
  auto whose = [&](int b) { return b < N ? pb.agents[static_cast<std::size_t>(b)].name + "'s workspace point" : pb.body_spec(b).name; };
  auto field = [&](int b) -> const Field& { return x0_fields[static_cast<std::size_t>(pb.body_agent(b))]; };
  for (int b = 0; b < B; ++b) {
    const AgentSpec& a = pb.body_spec(b);
    workspace_point3(*a.dynamics, a.workspace, a.x0.data(), p[static_cast<std::size_t>(b)].data());
    if (!p[static_cast<std::size_t>(b)].allFinite())
      field(b).fail("the workspace point of " + (b < N ? std::string("x0") : a.name + " at x0") + " is not finite: " +
                    point(p[static_cast<std::size_t>(b)]));
  }
  for (int b = 0; b < B; ++b) {
    const AgentSpec& a = pb.body_spec(b);
    const AgentSpec& owner = pb.agents[static_cast<std::size_t>(pb.body_agent(b))];
    const planning::Point& pt = p[static_cast<std::size_t>(b)];
    for (std::size_t oi = 0; oi < pb.obstacles.size(); ++oi) {
      const Obstacle& o = pb.obstacles[oi];
      // A staged obstacle binds at step 0 only on the first stage's way (its `avoid`).
      if (o.staged && (owner.stages.empty() || std::find(owner.stages[0].avoid.begin(), owner.stages[0].avoid.end(),
                                                         static_cast<int>(oi)) == owner.stages[0].avoid.end()))
        continue;
      // The real specification's own margins (spec_margins.hpp), with no tube around x0.
      const double depth = planning::obstacle_margin(o, pt, {}, 0.0, Norm::Two);
      const double clearance = pb.obstacle_clearance(b);
      const double margin = planning::obstacle_margin(o, pt, {}, clearance, pb.delta_norm);
      const std::string what = "x0 puts " + whose(b) + " " + point(pt);
      if (depth < 0) field(b).fail(what + " inside obstacle '" + o.name + "'");
      if (margin < 0)
        field(b).fail(what + " at " + norm + " distance " + number_text(margin + clearance) + " from obstacle '" + o.name +
                      "', less than " + (pb.delta_obstacles >= 0 ? "delta's obstacles = " : "delta = ") +
                      number_text(pb.obstacle_delta()) +
                      (a.radius > 0 ? " plus its radius " + number_text(a.radius) + " = " + number_text(clearance) : "") +
                      " (inside the obstacle grown by " + (a.radius > 0 ? "that" : "delta") + ")");
    }
  }
  // A formation pair (Euclidean distance within lambda +- mu at every time, t = 0 included).
  for (const auto& f : pb.formation) {
    const double d = (p[f.i] - p[f.j]).norm();
    if (planning::formation_margin(p[f.i], {}, p[f.j], {}, f.lambda, f.mu) < 0) {
      const std::size_t later = static_cast<std::size_t>(std::max(f.i, f.j));
      x0_fields[later].fail("x0 puts " + pb.agents[f.i].name + " and " + pb.agents[f.j].name + " " + number_text(d) +
                            " apart (Euclidean), outside their formation's lambda +- mu = [" +
                            number_text(f.lambda - f.mu) + ", " + number_text(f.lambda + f.mu) + "]");
    }
  }
  if (!pb.pairwise_collision) return;
  for (int j = 0; j < B; ++j)
    for (int i = 0; i < j; ++i) {
      if (pb.body_agent(i) == pb.body_agent(j)) continue;
      const double clearance = pb.pair_clearance(i, j);
      const planning::Point &pj = p[static_cast<std::size_t>(j)], &pi = p[static_cast<std::size_t>(i)];
      const double margin = planning::collision_margin(pj, {}, pi, {}, clearance, pb.delta_norm);
      const double dist = margin + clearance;
      const double ri = pb.body_spec(i).radius, rj = pb.body_spec(j).radius;
      const bool radii = ri > 0 || rj > 0;
      // The later agent's x0 is at fault (its start is the one read second).
      const int later = std::max(pb.body_agent(i), pb.body_agent(j));
      const int first = later == pb.body_agent(j) ? i : j, second = first == i ? j : i;
      if (margin < 0)
        x0_fields[static_cast<std::size_t>(later)].fail(
            "x0 puts " + (second < N ? pb.agents[static_cast<std::size_t>(second)].name : pb.body_spec(second).name) + " at " +
            point(p[static_cast<std::size_t>(second)]) + ", " + norm + " distance " + number_text(dist) + " from " +
            pb.body_spec(first).name + " at " + point(p[static_cast<std::size_t>(first)]) + " (agents[" +
            std::to_string(pb.body_agent(first)) + "]), less than delta = " + number_text(pb.delta) +
            (radii ? " plus their radii " + number_text(pb.body_spec(second).radius) + " and " +
                         number_text(pb.body_spec(first).radius) + " = " + number_text(clearance)
                   : ""));
    }
}

std::vector<Eigen::Vector2d> read_convex_polygon(const Field& p) {
  std::vector<Eigen::Vector2d> vertices;
  const auto items = p.items();
  if (items.size() < 3) p.fail("expected at least 3 vertices [[x, y], ...]");
  for (const auto& v : items) {
    const Eigen::VectorXd xy = v.vector(2, "a point in the plane");
    vertices.emplace_back(xy[0], xy[1]);
  }
  double area = 0;
  const std::size_t k = vertices.size();
  for (std::size_t i = 0; i < k; ++i) {
    const auto& a = vertices[i];
    const auto& b = vertices[(i + 1) % k];
    area += a.x() * b.y() - b.x() * a.y();
  }
  for (std::size_t i = 0; i < k; ++i)  // a zero-length edge has no outward normal
    if (vertices[i] == vertices[(i + 1) % k])
      items[(i + 1) % k].fail("this vertex repeats the one before it; list each corner once");
  if (std::abs(area) < 1e-12) p.fail("the polygon has no area");
  if (area < 0) std::reverse(vertices.begin(), vertices.end());  // store counter-clockwise
  for (std::size_t i = 0; i < k; ++i) {
    const Eigen::Vector2d e1 = vertices[(i + 1) % k] - vertices[i];
    const Eigen::Vector2d e2 = vertices[(i + 2) % k] - vertices[(i + 1) % k];
    if (e1.x() * e2.y() - e1.y() * e2.x() < -1e-12)
      p.fail("the polygon is not convex; split it into convex pieces");
  }
  return vertices;
}

// A disk {center: [x, y], radius: r} as the regular polygon around it: its inscribed circle is
// the disk (grown by a relative 1e-9, more than the rounding of the vertices' sin and cos), so a
// plan that keeps clear of the polygon keeps clear of the disk. 16 sides: at most 2 % wider
// than the disk, at the corners only; every stage (planners, checks, certificate) sees a polygon.
std::vector<Eigen::Vector2d> circumscribed_polygon(const Field& f) {
  f.expect_map();
  f.allow_only({"center", "radius"});
  const Eigen::VectorXd c = f.required("center").vector(2, "a point in the plane");
  const double r = f.required("radius").positive();
  constexpr int kSides = 16;
  const double pi = std::acos(-1.0);
  const double corner = r / std::cos(pi / kSides) * (1 + 1e-9) + 1e-12 * (1 + std::abs(c[0]) + std::abs(c[1]));
  std::vector<Eigen::Vector2d> v;
  for (int i = 0; i < kSides; ++i) {
    const double a = 2 * pi * (i + 0.5) / kSides;
    v.emplace_back(c[0] + corner * std::cos(a), c[1] + corner * std::sin(a));
  }
  return v;
}

// A 3-D workspace's obstacle is a vertical prism: the shape in x-y times `z: [lo, hi]` (a
// 3-entry box gives its own; without either, full height). In the plane neither is allowed.
void read_z_interval(const Field& z, int dim, Obstacle& o) {
  if (dim != 3)
    z.fail("a z interval needs a 3-D workspace (every agent's workspace: {position: [x, y, z]}); this problem's "
           "workspace is the plane");
  const Eigen::VectorXd v = z.vector(2, "an interval [z_lo, z_hi] of heights");
  if (v[0] > v[1]) z[0].fail("lower bound " + number_text(v[0]) + " exceeds upper bound " + number_text(v[1]));
  o.z_lo = v[0];
  o.z_hi = v[1];
}

Obstacle read_obstacle(const Field& f, std::size_t index, int dim) {
  f.expect_map();
  f.allow_only({"name", "box", "polygon", "circle", "scope", "z"});
  Obstacle o;
  o.name = f.child("name").present() ? f.child("name").text() : "obstacle" + std::to_string(index);
  if (Field sf = f.child("scope"); sf.present()) {
    if (!sf.is_scalar() || (sf.text() != "always" && sf.text() != "stages"))
      sf.fail("expected 'always' (every agent at every step, the default) or 'stages' (only on the mission stages "
              "that name it in 'avoid' or 'avoid_after')");
    o.staged = sf.text() == "stages";
  }
  if (f.child("name").present())
    if (const std::string why = name_defect(o.name); !why.empty()) f.child("name").fail(why);
  const bool has_box = f.child("box").present(), has_poly = f.child("polygon").present(),
             has_circle = f.child("circle").present();
  if (int{has_box} + int{has_poly} + int{has_circle} != 1) f.fail("expected exactly one of 'box', 'polygon' or 'circle'");
  if (Field z = f.child("z"); z.present()) read_z_interval(z, dim, o);
  if (has_circle) {
    o.vertices = circumscribed_polygon(f.child("circle"));
    return o;
  }
  if (has_box) {
    const Field bf = f.child("box");
    // In space a box gives 3 entries (or 2 and a `z` interval, or 2 for full height).
    const Field first = bf.child("lo").present() ? bf.child("lo") : bf.child("center");
    const bool box3 = dim == 3 && first.present() && first.is_sequence() && first.size() == 3;
    const Box b = read_box(bf, box3 ? 3 : 2, box3 ? "a box in space [x, y, z]" : dim == 3 ? "a box in space [x, y, z] (or [x, y] for the whole height)" : "a box in the plane: the agents' workspace is the plane; for boxes in space give each agent `workspace: {position: [x, y, z]}`");
    if (box3) {
      if (f.child("z").present()) f.child("z").fail("give the heights either in the box's third entries or in 'z', not both");
      o.z_lo = b.lo[2];
      o.z_hi = b.hi[2];
    }
    o.is_box = true;
    o.vertices = {{b.lo[0], b.lo[1]}, {b.hi[0], b.lo[1]}, {b.hi[0], b.hi[1]}, {b.lo[0], b.hi[1]}};
    return o;
  }
  o.vertices = read_convex_polygon(f.child("polygon"));
  return o;
}

int agent_index(const Problem& pb, const Field& f) {
  const std::string name = f.text();
  for (std::size_t i = 0; i < pb.agents.size(); ++i)
    if (pb.agents[i].name == name) return static_cast<int>(i);
  std::vector<std::string> names;
  for (const auto& a : pb.agents) names.push_back(a.name);
  f.fail("unknown agent '" + name + "'; agents: " + join(names));
}

void read_formation(const Field& f, Problem& pb) {
  if (f.is_sequence())  // a natural first guess: a list of pairs
    f.fail("expected a mapping {mu: tolerance, offsets: {agent: [x, y], ...}} and/or pairs: [{agents: [a, b], lambda: "
           "distance, mu: tolerance}, ...], not a list");
  f.expect_map();
  f.allow_only({"mu", "offsets", "pairs"});
  // A formation-wide tolerance, needed by `offsets` and by pairs that do not give their own.
  const std::optional<double> mu = f.child("mu").present() ? std::optional<double>(f.child("mu").positive()) : std::nullopt;
  if (Field off = f.child("offsets"); off.present()) {
    if (!mu) f.required("mu");  // the located "missing required field" error
    off.expect_map();
    std::vector<std::pair<int, Eigen::VectorXd>> pts;
    for (const auto& key : off.keys()) {
      Field k = off.child(key);
      YAML::Node name_node(key);
      const int i = agent_index(pb, Field(name_node, f.file(), k.path(), k.node().Mark()));
      const Eigen::VectorXd v = pb.workspace_dim == 3 ? k.vector(3, "an offset in space [x, y, z]")
                                                      : k.vector(2, "an offset in the plane");
      pts.emplace_back(i, v);
    }
    for (std::size_t a = 0; a < pts.size(); ++a)
      for (std::size_t b = a + 1; b < pts.size(); ++b)
        pb.formation.push_back({pts[a].first, pts[b].first, (pts[a].second - pts[b].second).norm(), *mu});
  }
  if (Field pairs = f.child("pairs"); pairs.present()) {
    for (const auto& p : pairs.items()) {
      p.expect_map();
      p.allow_only({"agents", "lambda", "mu"});
      Field ag = p.required("agents");
      if (!ag.is_sequence() || ag.size() != 2) ag.fail("expected two agent names [a, b]");
      const int i = agent_index(pb, ag[0]), j = agent_index(pb, ag[1]);
      if (i == j) ag.fail("a formation pair needs two different agents");
      const double lambda = p.required("lambda").positive();
      if (!p.child("mu").present() && !mu)
        p.fail("missing the tolerance 'mu': give it in this pair or once for the whole formation (formation: {mu: ...})");
      pb.formation.push_back({i, j, lambda, p.child("mu").present() ? p.child("mu").positive() : *mu});
    }
  }
  if (pb.formation.empty()) f.fail("expected 'offsets' or 'pairs' defining at least one formation pair");
  for (const auto& fp : pb.formation)
    if (fp.mu <= 0 || fp.lambda - fp.mu < 0) f.fail("formation tolerance mu must be positive and below lambda");
}

// Obstacles as a distance plugin's `polygons` parameter: vertex count, then x, y per vertex.
std::vector<double> polygon_param(const std::vector<std::vector<Eigen::Vector2d>>& polygons) {
  std::vector<double> flat;
  for (const auto& poly : polygons) {
    flat.push_back(static_cast<double>(poly.size()));
    for (const auto& v : poly) flat.insert(flat.end(), {v.x(), v.y()});
  }
  return flat;
}

// `collision`: `exact` (core's own geometry, the default) or a distance plugin such as `fcl`,
// which then computes the obstacle distances the planners' constraints use. Creating it once on
// the problem's own obstacles here makes a broken plugin fail at load time, not mid-plan.
void read_collision(const Field& f, LoadedProblem& out) {
  Problem& pb = out.problem;
  const PluginField pf = read_plugin_field(f, "name");
  if (pf.name == "exact") {
    if (pf.params_field.present()) pf.params_field.fail("core's exact geometry takes no parameters");
    return;
  }
  const PluginRegistry& reg = *out.registry;
  const PluginInfo* info = reg.find(PluginKind<DistanceModel>::name, pf.name);
  if (!info) {
    std::string msg = unknown_plugin(reg, PluginKind<DistanceModel>::name, pf.name);
    pf.name_field.fail(msg + " (or 'exact' for core's own geometry)");
  }
  // Distance plugins take planar polygons; a prism bounded in z is not one.
  for (const auto& o : pb.obstacles)
    if (o.z_bounded())
      pf.name_field.fail("the collision plugin '" + pf.name + "' measures distances to planar polygons, but obstacle '" +
                         o.name + "' is bounded in z (a 3-D workspace's prism); use 'exact' (core's geometry, "
                         "which judges prisms) or give every obstacle the whole height");
  Params user = read_params(pf.params_field, *info);
  for (const char* reserved : {"polygons", "boxes"})
    if (user.has(reserved))
      pf.params_field.child(reserved).fail("set by marsyn from the problem's `obstacles`; remove it here");
  std::vector<std::vector<Eigen::Vector2d>> own;
  for (const auto& o : pb.obstacles) own.push_back(o.vertices);
  auto registry = out.registry;
  const std::string name = pf.name;
  pb.distance_model = [registry, name, user](const std::vector<std::vector<Eigen::Vector2d>>& polygons) {
    Params p = user;
    p.set("polygons", polygon_param(polygons));
    return std::shared_ptr<const DistanceModel>(registry->create<DistanceModel>(name, p));
  };
  try {
    pb.distance_model(own);
  } catch (const ParamError& e) {
    pf.name_field.fail(std::string("the plugin rejected the problem's obstacles: ") + e.what());
  } catch (const std::exception& e) {
    pf.name_field.fail(std::string("the plugin could not be created: ") + e.what());
  }
  pb.collision.name = name;
  pb.collision.params = user;
}

}  // namespace marsyn::loader
