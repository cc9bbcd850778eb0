#include "marsyn/core/problem/problem_loader.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include <climits>

#include "marsyn/core/problem/agent_checks.hpp"
#include "marsyn/core/problem/input_limits.hpp"
#include "marsyn/core/planning/geometry.hpp"
#include "marsyn/core/tracking/tracker_choice.hpp"
#include "equations/equation_yaml.hpp"
#include "yaml_reader.hpp"

namespace fs = std::filesystem;

namespace marsyn {
namespace {

using yaml::Field;

const std::vector<std::string> kTopKeys = {
    "name",  "description", "tau",     "horizon",      "rk4_substeps", "delta",     "delta_norm",
    "pairwise_collision", "guarantee", "planner", "tracker", "collision", "plugin_paths", "defaults", "agents", "obstacles",
    "formation"};
const std::vector<std::string> kAgentKeys = {"name",         "dynamics",    "x0",    "goal",
                                             "state_bounds", "input_bounds", "disturbance", "eps",
                                             "eta_x",        "eta_u",        "workspace",   "tracker"};

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& i : items) out += (out.empty() ? "" : ", ") + i;
  return out.empty() ? "(none found)" : out;
}

// An agent's field comes from its own block or, when absent there, from `defaults`.
Field agent_field(const Field& agent, const Field& defaults, const std::string& key) {
  Field f = agent.child(key);
  return f.present() ? f : defaults.child(key);
}

Field agent_required(const Field& agent, const Field& defaults, const std::string& key) {
  Field f = agent_field(agent, defaults, key);
  if (!f.present()) agent.fail("missing required field '" + key + "' (set it in the agent or in 'defaults')");
  return f;
}

std::string unknown_plugin(const PluginRegistry& reg, const std::string& kind, const std::string& name) {
  std::string msg = "unknown " + kind + " plugin '" + name + "'";
  const std::string near = yaml::nearest(name, reg.names(kind));
  if (!near.empty()) msg += " (did you mean '" + near + "'?)";
  msg += "; available: " + join(reg.names(kind));
  for (const auto& p : reg.problems())
    if (p.reason.find("API version") != std::string::npos) msg += "; skipped " + p.library_path + ": " + p.reason;
  return msg;
}

// A declared range such as "[1, inf)", "[0, 12]" or "-1 or [0, inf)"; false when the text is
// not of that form (the range is then documentation only).
bool in_declared_range(const std::string& range, long v, bool* understood) {
  *understood = false;
  auto trim = [](std::string t) {
    while (!t.empty() && t.front() == ' ') t.erase(0, 1);
    while (!t.empty() && t.back() == ' ') t.pop_back();
    return t;
  };
  auto number = [&](const std::string& t, double* out) {
    const std::string u = trim(t);
    if (u == "inf" || u == "+inf") return *out = INFINITY, true;
    if (u == "-inf") return *out = -INFINITY, true;
    if (u.empty()) return false;
    char* end = nullptr;
    *out = std::strtod(u.c_str(), &end);
    return end && *end == '\0';
  };
  std::vector<std::string> parts;
  std::string rest = range;
  for (std::size_t at; (at = rest.find(" or ")) != std::string::npos; rest = rest.substr(at + 4))
    parts.push_back(rest.substr(0, at));
  parts.push_back(rest);
  bool inside = false;
  for (const auto& raw : parts) {
    const std::string p = trim(raw);
    double a = 0, b = 0;
    if (number(p, &a)) {
      inside = inside || static_cast<double>(v) == a;
      continue;
    }
    const auto comma = p.find(',');
    if (p.size() < 5 || comma == std::string::npos || (p.front() != '[' && p.front() != '(') ||
        (p.back() != ']' && p.back() != ')') || !number(p.substr(1, comma - 1), &a) ||
        !number(p.substr(comma + 1, p.size() - comma - 2), &b))
      return true;  // not understood: no check
    const double x = static_cast<double>(v);
    inside = inside || ((p.front() == '[' ? x >= a : x > a) && (p.back() == ']' ? x <= b : x < b));
  }
  *understood = true;
  return inside;
}

// Integer parameters are range-checked here, before a plugin narrows them (plugins store them as
// int): the 32-bit range first, then the range the plugin declares.
long checked_integer(const Field& v, const ParamSpec& spec, const PluginInfo& info) {
  const long x = v.integer_in(INT_MIN, INT_MAX, "integer plugin parameters are 32-bit");
  bool understood = false;
  if (!in_declared_range(spec.range, x, &understood) && understood)
    v.fail("expected an integer in " + spec.range + " (the range the " + info.kind + " '" + info.name +
           "' declares), got " + std::to_string(x));
  return x;
}

Params read_params(const Field& f, const PluginInfo& info) {
  Params params;
  if (!f.present()) return params;
  f.expect_map();
  std::vector<std::string> allowed;
  for (const auto& s : info.params) allowed.push_back(s.name);
  if (allowed.empty() && !f.keys().empty())
    f.child(f.keys().front()).fail("the " + info.kind + " '" + info.name + "' takes no parameters");
  f.allow_only(allowed);
  for (const auto& spec : info.params) {
    Field v = f.child(spec.name);
    if (!v.present()) continue;
    switch (spec.type) {
      case ParamType::Bool: params.set(spec.name, v.boolean()); break;
      case ParamType::Int: params.set(spec.name, checked_integer(v, spec, info)); break;
      case ParamType::Real: params.set(spec.name, v.real()); break;
      case ParamType::String: params.set(spec.name, v.text()); break;
      case ParamType::RealVector: {
        const Eigen::VectorXd x = v.vector(-1, "");
        params.set(spec.name, std::vector<double>(x.data(), x.data() + x.size()));
        break;
      }
    }
  }
  return params;
}

// A plugin choice written either as `name` or as {name: ..., params: {...}} (dynamics use `type`).
struct PluginField {
  std::string name;
  Field name_field;
  Field params_field;
};

PluginField read_plugin_field(const Field& f, const std::string& name_key, const std::string& extra_key = {}) {
  if (f.is_scalar()) return {f.text(), f, f.child("params")};
  f.expect_map();
  if (extra_key.empty()) f.allow_only({name_key, "params"});
  else f.allow_only({name_key, "params", extra_key});
  Field n = f.required(name_key);
  return {n.text(), n, f.child("params")};
}

template <class Interface>
std::pair<std::shared_ptr<Interface>, Params> create_plugin(const PluginRegistry& reg, const PluginField& pf) {
  const std::string kind = PluginKind<Interface>::name;
  const PluginInfo* info = reg.find(kind, pf.name);
  if (!info) pf.name_field.fail(unknown_plugin(reg, kind, pf.name));
  Params params = read_params(pf.params_field, *info);
  try {
    return {reg.create<Interface>(pf.name, params), params};
  } catch (const ParamError& e) {
    Field at = pf.params_field.child(e.field());
    (at.present() ? at : pf.params_field.present() ? pf.params_field : pf.name_field).fail(e.what());
  } catch (const std::exception& e) {
    pf.name_field.fail(std::string("the plugin could not be created: ") + e.what());
  }
}

Box read_box(const Field& f, int n, const std::string& why) {
  f.expect_map();
  Box b;
  if (f.child("center").present() || f.child("radius").present()) {
    f.allow_only({"center", "radius"});
    const Eigen::VectorXd c = f.required("center").vector(n, why);
    const Eigen::VectorXd r = f.required("radius").non_negative_vector(n, why);
    b = {c - r, c + r};
  } else {
    f.allow_only({"lo", "hi"});
    b = {f.required("lo").vector(n, why), f.required("hi").vector(n, why)};
    for (int i = 0; i < n; ++i)
      if (b.lo[i] > b.hi[i])
        f.child("lo")[static_cast<std::size_t>(i)].fail("lower bound " + fmt(b.lo[i]) + " exceeds upper bound " +
                                                         fmt(b.hi[i]));
  }
  return b;
}

Workspace read_workspace(const Field& f, const Dynamics& dyn) {
  f.expect_map();
  f.allow_only({"position", "offset", "footprint"});
  Workspace ws;
  const int n = dyn.state_dim();
  if (f.child("footprint").present()) {
    if (f.child("position").present()) f.child("position").fail("give either 'position' or 'footprint', not both");
    const std::string name = f.child("footprint").text();
    const auto names = dyn.footprints();
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) ws.footprint = static_cast<int>(i);
    if (ws.footprint < 0)
      f.child("footprint").fail("the dynamics '" + dyn.type() + "' has no footprint '" + name +
                                "'; it has: " + join(names));
    ws.footprint_name = name;
    return ws;
  }
  Field pos = f.required("position");
  if (!pos.is_sequence() || pos.size() != 2)
    pos.fail("expected 2 entries [x_index, y_index]: state indices (0-based) or null for a fixed coordinate");
  for (std::size_t c = 0; c < 2; ++c) {
    Field e = pos[c];
    if (!e.present()) {
      ws.index[c] = -1;
      continue;
    }
    const long i = e.integer();
    if (i < 0 || i >= n)
      e.fail("expected a state index in [0, " + std::to_string(n - 1) + "] (the dynamics '" + dyn.type() +
             "' has " + std::to_string(n) + " states) or null");
    ws.index[c] = static_cast<int>(i);
  }
  if (f.child("offset").present()) {
    const Eigen::VectorXd o = f.child("offset").vector(2, "a point in the plane");
    ws.offset = {o[0], o[1]};
  }
  return ws;
}

void validate_agent(const AgentSpec& a, const Field& x0f, const Field& goalf) {
  const auto names = a.dynamics->state_names();
  for (int i = 0; i < a.n(); ++i) {
    const std::string coord = "'" + names[i] + "'";
    const std::size_t si = static_cast<std::size_t>(i);
    const double lo = a.state_bounds.lo[i], hi = a.state_bounds.hi[i];
    switch (agent_defect(a, i)) {
      case AgentDefect::None:
        break;
      case AgentDefect::X0OutsideBounds:
        x0f[si].fail("x0 = " + fmt(a.x0[i]) + " in " + coord + " lies outside the state bounds [" + fmt(lo) + ", " +
                     fmt(hi) + "]");
      case AgentDefect::TubeOutsideBounds:
        x0f[si].fail("the tube around x0 leaves the state bounds in " + coord + ": x0 +- eps = [" +
                     fmt(a.x0[i] - a.eps[i]) + ", " + fmt(a.x0[i] + a.eps[i]) + "] is not inside [" + fmt(lo) +
                     ", " + fmt(hi) + "]");
      case AgentDefect::GoalEmpty:
        goalf.fail("the goal shrunk by eps is empty in " + coord + ": [" + fmt(a.goal.lo[i]) + " + " +
                   fmt(a.eps[i]) + ", " + fmt(a.goal.hi[i]) + " - " + fmt(a.eps[i]) + "] = [" +
                   fmt(a.goal.lo[i] + a.eps[i]) + ", " + fmt(a.goal.hi[i] - a.eps[i]) +
                   "]; enlarge the goal or reduce eps");
      case AgentDefect::GoalOutsideBounds:
        goalf.fail("the goal [" + fmt(a.goal.lo[i]) + ", " + fmt(a.goal.hi[i]) + "] in " + coord +
                   " lies outside the state bounds [" + fmt(lo) + ", " + fmt(hi) + "]");
      case AgentDefect::GoalUnreachable:
        goalf.fail("no eps-robust final state in " + coord + ": the goal shrunk by eps [" +
                   fmt(a.goal.lo[i] + a.eps[i]) + ", " + fmt(a.goal.hi[i] - a.eps[i]) +
                   "] and the state bounds shrunk by eps [" + fmt(lo + a.eps[i]) + ", " + fmt(hi - a.eps[i]) +
                   "] do not overlap; move the goal inside the state bounds or reduce eps");
    }
  }
}

// `tracker` as written: a tracker's name or block ({name, params}), or `auto` (also when absent).
struct TrackerRequest {
  bool automatic = true;
  PluginChoice choice;
  Field field;  // where it was written (not present: the default, auto)
};

TrackerRequest read_tracker_request(const Field& f, const PluginRegistry& reg) {
  TrackerRequest r{true, {}, f};
  if (!f.present()) return r;
  const PluginField pf = read_plugin_field(f, "name");
  if (pf.name == kAutoTracker) {
    if (pf.params_field.present())
      pf.params_field.fail("'auto' takes no parameters; name the tracker to set its parameters, e.g. "
                           "{name: abcd, params: {...}}");
    return r;
  }
  r.automatic = false;
  r.choice.name = pf.name;
  r.choice.params = create_plugin<Tracker>(reg, pf).second;
  return r;
}

// Where an assessment's field is written for this agent: the agent's own field or the default,
// element `coordinate` of it when given; a tracker parameter in the tracker block; else the agent.
Field assessment_field(const TrackerAssessment& as, const Field& af, const Field& defaults, const Field& tracker_field) {
  if (as.field.empty()) return af;
  const Field own = agent_field(af, defaults, as.field);
  const Field param = tracker_field.is_map() ? tracker_field.child("params").child(as.field) : own;
  const Field& f = own.present() ? own : param;
  if (!f.present()) return af;
  if (as.coordinate >= 0 && f.is_sequence() && static_cast<std::size_t>(as.coordinate) < f.size())
    return f[static_cast<std::size_t>(as.coordinate)];
  return f;
}

// Resolves the agent's tracker (AgentSpec::tracker) by the trackers' own assessments; a refusal
// (or, for auto, every tracker's) is a located error at the field the tracker names.
AgentTrackers resolve_tracker(AgentSpec& a, const TrackerRequest& req, TrackerInstances& trackers,
                              const PluginRegistry& reg, const Problem& pb, const Field& af, const Field& defaults) {
  AgentTrackers out;
  out.automatic = req.automatic;
  if (!req.automatic) {
    const TrackerAssessment as = assess_tracker(trackers, req.choice, a, pb.horizon, pb.tau);
    out.asked.emplace_back(req.choice.name, as);
    if (!as.ok) assessment_field(as, af, defaults, req.field).fail(as.message);
    a.tracker = req.choice;
    out.assessment = as;
    return out;
  }
  // Asked in name order, so that the choice among equal estimates and the location of a refusal
  // do not depend on where the plugins were found.
  std::vector<std::string> names = reg.names(PluginKind<Tracker>::name);
  std::sort(names.begin(), names.end());
  if (names.empty())
    (req.field.present() ? req.field : af)
        .fail("no tracker plugin is installed (tracker: auto chooses among the installed ones); set MARSYN_PLUGIN_PATH "
              "or plugin_paths");
  std::vector<std::pair<double, std::size_t>> ok;  // (work_s, index into asked)
  for (const auto& name : names) {
    const TrackerAssessment as = assess_tracker(trackers, {name, {}}, a, pb.horizon, pb.tau);
    if (as.ok) ok.emplace_back(as.work_s, out.asked.size());
    out.asked.emplace_back(name, as);
  }
  if (ok.empty()) {
    const TrackerAssessment& first = out.asked.front().second;
    std::string msg;
    if (out.asked.size() == 1) {
      msg = first.message + " (tracker: auto, and " + out.asked.front().first + " is the only tracker installed)";
    } else {
      msg = "no installed tracker accepts this agent (tracker: auto):";
      for (std::size_t i = 0; i < out.asked.size(); ++i)
        msg += std::string(i ? ";" : "") + " " + out.asked[i].first + ": " + out.asked[i].second.message;
    }
    assessment_field(first, af, defaults, req.field).fail(msg);
  }
  std::stable_sort(ok.begin(), ok.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  a.tracker = {out.asked[ok.front().second].first, {}};
  out.assessment = out.asked[ok.front().second].second;
  for (std::size_t i = 1; i < ok.size(); ++i) out.fallbacks.push_back({out.asked[ok[i].second].first, {}});
  return out;
}

// The real specification at k = 0, with the exact geometry of the robustness check
// (planning/geometry.hpp): each agent's workspace point at x0 keeps delta from every obstacle and
// from every other agent. A start violating it can never be planned for.
double inf_distance(const planning::Polygon& poly, const Eigen::Vector2d& p, double upper) {
  // The r with p on the boundary of poly grown by the box (r, r): bisection on the exact test.
  double lo = 0, hi = upper;
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (planning::signed_distance(planning::grow_by_box(poly, mid, mid), p) < 0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

std::string point(const Eigen::Vector2d& p) { return "(" + fmt(p.x()) + ", " + fmt(p.y()) + ")"; }

void check_start_geometry(const Problem& pb, const std::vector<Field>& x0_fields) {
  const bool inf = pb.delta_norm == Norm::Inf;
  const std::string norm = inf ? "inf-norm" : "Euclidean";
  std::vector<Eigen::Vector2d> p(pb.agents.size());
  for (std::size_t i = 0; i < pb.agents.size(); ++i) {
    const AgentSpec& a = pb.agents[i];
    workspace_point(*a.dynamics, a.workspace, a.x0.data(), p[i].data());
    if (!p[i].allFinite()) x0_fields[i].fail("the workspace point of x0 is not finite: " + point(p[i]));
  }
  for (std::size_t i = 0; i < pb.agents.size(); ++i) {
    const AgentSpec& a = pb.agents[i];
    for (const auto& o : pb.obstacles) {
      const double inside = planning::signed_distance(o.vertices, p[i]);
      const std::string what = "x0 puts " + a.name + "'s workspace point " + point(p[i]);
      if (inside < 0) x0_fields[i].fail(what + " inside obstacle '" + o.name + "'");
      const bool near = inf ? planning::signed_distance(planning::grow_by_box(o.vertices, pb.delta, pb.delta), p[i]) < 0
                            : inside < pb.delta;
      if (near) {
        const double d = inf ? inf_distance(o.vertices, p[i], pb.delta) : inside;
        x0_fields[i].fail(what + " at " + norm + " distance " + fmt(d) + " from obstacle '" + o.name +
                          "', less than delta = " + fmt(pb.delta) + " (inside the obstacle grown by delta)");
      }
    }
  }
  if (!pb.pairwise_collision) return;
  for (std::size_t j = 0; j < pb.agents.size(); ++j)
    for (std::size_t i = 0; i < j; ++i) {
      const Eigen::Vector2d d = p[j] - p[i];
      const double dist = inf ? d.cwiseAbs().maxCoeff() : d.norm();
      if (dist < pb.delta)
        x0_fields[j].fail("x0 puts " + pb.agents[j].name + " at " + point(p[j]) + ", " + norm + " distance " + fmt(dist) +
                          " from " + pb.agents[i].name + " at " + point(p[i]) + " (agents[" + std::to_string(i) +
                          "]), less than delta = " + fmt(pb.delta));
    }
}

Obstacle read_obstacle(const Field& f, std::size_t index) {
  f.expect_map();
  f.allow_only({"name", "box", "polygon"});
  Obstacle o;
  o.name = f.child("name").present() ? f.child("name").text() : "obstacle" + std::to_string(index);
  if (f.child("name").present())
    if (const std::string why = name_defect(o.name); !why.empty()) f.child("name").fail(why);
  const bool has_box = f.child("box").present(), has_poly = f.child("polygon").present();
  if (has_box == has_poly) f.fail("expected exactly one of 'box' or 'polygon'");
  if (has_box) {
    const Box b = read_box(f.child("box"), 2, "a box in the plane");
    o.is_box = true;
    o.vertices = {{b.lo[0], b.lo[1]}, {b.hi[0], b.lo[1]}, {b.hi[0], b.hi[1]}, {b.lo[0], b.hi[1]}};
    return o;
  }
  Field p = f.child("polygon");
  const auto items = p.items();
  if (items.size() < 3) p.fail("expected at least 3 vertices [[x, y], ...]");
  for (const auto& v : items) {
    const Eigen::VectorXd xy = v.vector(2, "a point in the plane");
    o.vertices.emplace_back(xy[0], xy[1]);
  }
  double area = 0;
  const std::size_t k = o.vertices.size();
  for (std::size_t i = 0; i < k; ++i) {
    const auto& a = o.vertices[i];
    const auto& b = o.vertices[(i + 1) % k];
    area += a.x() * b.y() - b.x() * a.y();
  }
  if (std::abs(area) < 1e-12) p.fail("the polygon has no area");
  if (area < 0) std::reverse(o.vertices.begin(), o.vertices.end());  // store counter-clockwise
  for (std::size_t i = 0; i < k; ++i) {
    const Eigen::Vector2d e1 = o.vertices[(i + 1) % k] - o.vertices[i];
    const Eigen::Vector2d e2 = o.vertices[(i + 2) % k] - o.vertices[(i + 1) % k];
    if (e1.x() * e2.y() - e1.y() * e2.x() < -1e-12)
      p.fail("the polygon is not convex; split it into convex pieces");
  }
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
  f.expect_map();
  f.allow_only({"mu", "offsets", "pairs"});
  const double mu = f.required("mu").positive();
  if (Field off = f.child("offsets"); off.present()) {
    off.expect_map();
    std::vector<std::pair<int, Eigen::Vector2d>> pts;
    for (const auto& key : off.keys()) {
      Field k = off.child(key);
      YAML::Node name_node(key);
      const int i = agent_index(pb, Field(name_node, f.file(), k.path(), k.node().Mark()));
      const Eigen::VectorXd v = k.vector(2, "an offset in the plane");
      pts.emplace_back(i, Eigen::Vector2d(v[0], v[1]));
    }
    for (std::size_t a = 0; a < pts.size(); ++a)
      for (std::size_t b = a + 1; b < pts.size(); ++b)
        pb.formation.push_back({pts[a].first, pts[b].first, (pts[a].second - pts[b].second).norm(), mu});
  }
  if (Field pairs = f.child("pairs"); pairs.present()) {
    for (const auto& p : pairs.items()) {
      p.expect_map();
      p.allow_only({"agents", "lambda", "mu"});
      Field ag = p.required("agents");
      if (!ag.is_sequence() || ag.size() != 2) ag.fail("expected two agent names [a, b]");
      const int i = agent_index(pb, ag[0]), j = agent_index(pb, ag[1]);
      if (i == j) ag.fail("a formation pair needs two different agents");
      pb.formation.push_back({i, j, p.required("lambda").positive(), p.child("mu").present() ? p.child("mu").positive() : mu});
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

}  // namespace

LoadedProblem load_problem(const std::string& path) {
  const YAML::Node root = yaml::load_file(path);
  Field top(root, path, "");
  top.expect_map();
  top.allow_only(kTopKeys);

  LoadedProblem out;
  Problem& pb = out.problem;
  pb.source = path;
  pb.name = top.child("name").present() ? top.child("name").text() : name_from_stem(fs::path(path).stem().string());
  if (top.child("name").present())
    if (const std::string why = name_defect(pb.name); !why.empty()) top.child("name").fail(why);

  // Plugins first: the dynamics decide every dimension checked below.
  const fs::path base = fs::path(path).parent_path();
  std::vector<std::string> plugin_paths;
  if (Field pp = top.child("plugin_paths"); pp.present()) {
    for (const auto& item : pp.items()) {
      fs::path p = item.text();
      if (p.is_relative()) p = base / p;
      plugin_paths.push_back(p.lexically_normal().string());
    }
  }
  pb.plugin_paths = plugin_paths;
  out.registry = std::make_shared<PluginRegistry>(plugin_paths);
  for (const auto& prob : out.registry->problems()) {
    if (!prob.explicit_path) continue;
    Field pp = top.child("plugin_paths");
    for (std::size_t i = 0; i < plugin_paths.size(); ++i)
      if (prob.library_path.rfind(plugin_paths[i], 0) == 0) pp[i].fail("plugin library " + prob.library_path + " " + prob.reason);
    pp.fail("plugin library " + prob.library_path + " " + prob.reason);
  }

  pb.tau = top.required("tau").positive();
  pb.horizon = static_cast<int>(top.required("horizon").integer_in(1, kMaxHorizon, "steps"));
  if (Field f = top.child("rk4_substeps"); f.present())
    pb.rk4_substeps = static_cast<int>(f.integer_in(1, kMaxRk4Substeps, "RK4 substeps per step"));
  if (Field f = top.child("delta"); f.present()) pb.delta = f.non_negative();
  if (Field f = top.child("delta_norm"); f.present()) {
    const std::string s = f.text();
    if (s == "inf" || s == "max") pb.delta_norm = Norm::Inf;
    else if (s == "2" || s == "euclidean") pb.delta_norm = Norm::Two;
    else f.fail("expected 'inf' or '2', got '" + s + "'");
  }
  if (Field f = top.child("pairwise_collision"); f.present()) pb.pairwise_collision = f.boolean();
  if (Field f = top.child("guarantee"); f.present()) {
    const std::string s = f.text();
    if (s == "continuous") pb.guarantee = Guarantee::Continuous;
    else if (s == "sampled") pb.guarantee = Guarantee::Sampled;
    else f.fail("expected 'continuous' (safe for every t, the default) or 'sampled' (only at t = k tau, the paper's semantics), got '" + s + "'");
  }

  const Field defaults = top.child("defaults");
  if (defaults.present()) {
    defaults.expect_map();
    std::vector<std::string> allowed(kAgentKeys.begin() + 1, kAgentKeys.end());
    defaults.allow_only(allowed);
  }
  const bool has_obstacles = top.child("obstacles").present() && top.child("obstacles").size() > 0;

  Field agents = top.required("agents");
  const auto agent_fields = agents.items();
  if (agent_fields.empty()) agents.fail("expected at least one agent");
  if (agent_fields.size() > kMaxAgents)
    agents.fail("expected at most " + std::to_string(kMaxAgents) + " agents, got " + std::to_string(agent_fields.size()));
  const bool spatial = has_obstacles || top.child("formation").present() ||
                       (pb.pairwise_collision && agent_fields.size() > 1);
  std::map<std::string, std::size_t> seen;
  std::vector<Field> x0_fields;
  // The top-level tracker (default of every agent without its own): a name, a block, or auto.
  const TrackerRequest top_tracker = read_tracker_request(top.child("tracker"), *out.registry);
  pb.tracker = top_tracker.automatic ? PluginChoice{kAutoTracker, {}} : top_tracker.choice;
  TrackerInstances tracker_instances(out.registry);
  for (std::size_t idx = 0; idx < agent_fields.size(); ++idx) {
    const Field& af = agent_fields[idx];
    af.expect_map();
    af.allow_only(kAgentKeys);
    AgentSpec a;
    Field name = af.required("name");
    a.name = name.text();
    if (const std::string why = name_defect(a.name); !why.empty()) name.fail(why);
    if (auto it = seen.find(a.name); it != seen.end())
      name.fail("duplicate agent name '" + a.name + "' (also agents[" + std::to_string(it->second) + "])");
    seen[a.name] = idx;

    // A plugin name, or equations written in the file (core/src/equations, issue 15).
    const Field dyn_field = agent_required(af, defaults, "dynamics");
    if (equations::is_equation_model(dyn_field, defaults.child("dynamics"))) {
      a.dynamics = equations::load_equation_dynamics(dyn_field, defaults.child("dynamics"));
      a.dynamics_type = a.dynamics->type();
    } else {
      const PluginField dyn = read_plugin_field(dyn_field, "type");
      a.dynamics_type = dyn.name;
      a.dynamics = create_plugin<Dynamics>(*out.registry, dyn).first;
    }
    const int n = a.dynamics->state_dim(), m = a.dynamics->input_dim();
    const std::string sn = "the dynamics '" + a.dynamics_type + "' has " + std::to_string(n) + " states";
    const std::string sm = "the dynamics '" + a.dynamics_type + "' has " + std::to_string(m) + " inputs";

    Field x0f = af.required("x0");
    a.x0 = x0f.vector(n, sn);
    Field goalf = agent_required(af, defaults, "goal");
    a.goal = read_box(goalf, n, sn);
    a.state_bounds = read_box(agent_required(af, defaults, "state_bounds"), n, sn);
    a.input_bounds = read_box(agent_required(af, defaults, "input_bounds"), m, sm);
    a.w = agent_required(af, defaults, "disturbance").non_negative_vector(n, sn);
    a.eps = agent_required(af, defaults, "eps").positive_vector(n, sn);
    // The grids are optional: only a grid tracker (abcd) reads them, and its assessment asks for
    // them when they are missing.
    if (Field etaf = agent_field(af, defaults, "eta_x"); etaf.present()) a.eta_x = etaf.positive_vector(n, sn);
    if (Field etauf = agent_field(af, defaults, "eta_u"); etauf.present()) a.eta_u = etauf.positive_vector(m, sm);
    if (Field ws = agent_field(af, defaults, "workspace"); ws.present()) {
      a.workspace = read_workspace(ws, *a.dynamics);
    } else if (spatial) {
      af.fail("missing required field 'workspace' (the problem has obstacles, collisions or a formation, so "
              "each agent needs a point in the plane: {position: [i, j]} or {footprint: name})");
    } else {
      a.workspace.index = {0, n > 1 ? 1 : -1};
    }
    validate_agent(a, x0f, goalf);
    memory_budget_bytes();  // a malformed MARSYN_MEMORY_BUDGET is reported before any tracker reads it
    // The agent's own tracker, else the default's, else the top level's (Fields are never
    // assigned: a YAML::Node assignment would write into the document).
    const Field tf = agent_field(af, defaults, "tracker");
    const TrackerRequest req = tf.present() ? read_tracker_request(tf, *out.registry) : top_tracker;
    out.trackers.push_back(resolve_tracker(a, req, tracker_instances, *out.registry, pb, af, defaults));
    x0_fields.push_back(x0f);
    pb.agents.push_back(std::move(a));
  }

  if (has_obstacles) {
    const auto obs = top.child("obstacles").items();
    for (std::size_t i = 0; i < obs.size(); ++i) pb.obstacles.push_back(read_obstacle(obs[i], i));
  }
  if (Field f = top.child("formation"); f.present()) read_formation(f, pb);
  check_start_geometry(pb, x0_fields);
  {
    std::string source;
    const double budget = memory_budget_bytes(&source);
    const MemoryEstimate e = planner_memory(pb);
    if (!(e.bytes <= budget)) {
      // Blame the horizon when a horizon of 1000 steps would fit, the agent count otherwise.
      const bool pairs = e.bytes / (pb.horizon + 1.0) * 1001 > budget;
      (pairs ? top.child("agents") : top.child("horizon"))
          .fail("planning would need about " + format_bytes(e.bytes) + " (" + e.detail + "), more than the memory budget of " +
                format_bytes(budget) + " (" + source + "); " +
                (pairs ? "use fewer agents" : "shorten the horizon"));
    }
  }

  // Planner: the default when absent; always checked against the installed plugins so that a
  // typo fails here rather than after minutes of work. (Trackers: per agent, above.)
  {
    Field f = top.child("planner");
    if (!f.present() && !out.registry->find("planner", kDefaultPlanner))
      throw ConfigError(path, 0, 0, "planner",
                        std::string("no planner given and the default '") + kDefaultPlanner +
                            "' is not installed; available: " + join(out.registry->names("planner")));
    PluginField pf = f.present() ? read_plugin_field(f, "name", "warm_start")
                                 : PluginField{kDefaultPlanner, Field(YAML::Node(kDefaultPlanner), path, "planner"),
                                               Field(YAML::Node(), path, "planner.params")};
    pb.planner.name = pf.name;
    pb.planner.params = create_plugin<Planner>(*out.registry, pf).second;
  }
  // planner.warm_start: a planner whose plan starts the main one (docs/planner.md, chains).
  if (Field p = top.child("planner"); p.present() && !p.is_scalar())
    if (Field w = p.child("warm_start"); w.present()) {
      const PluginField wf = read_plugin_field(w, "name");
      pb.warm_start_planner.name = wf.name;
      pb.warm_start_planner.params = create_plugin<Planner>(*out.registry, wf).second;
    }
  if (Field f = top.child("collision"); f.present()) read_collision(f, out);
  return out;
}

}  // namespace marsyn
