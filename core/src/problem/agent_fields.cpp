#include "agent_fields.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "field_text.hpp"
#include "marsyn/core/problem/agent_checks.hpp"
#include "plugin_fields.hpp"

namespace marsyn::loader {

Field agent_field(const Field& agent, const Field& defaults, const std::string& key) {
  Field f = agent.child(key);
  return f.present() ? f : defaults.child(key);
}

Field agent_required(const Field& agent, const Field& defaults, const std::string& key) {
  Field f = agent_field(agent, defaults, key);
  if (!f.present()) agent.fail("missing required field '" + key + "' (set it in the agent or in 'defaults')");
  return f;
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
        f.child("lo")[static_cast<std::size_t>(i)].fail("lower bound " + number_text(b.lo[i]) +
                                                        " exceeds upper bound " + number_text(b.hi[i]));
  }
  return b;
}

// One entry of `position`: a state index (0-based) or a state's name, as `marsyn plugins` and
// the equations list them.
static int position_index(const Field& e, const Dynamics& dyn) {
  const int n = dyn.state_dim();
  const auto names = dyn.state_names();
  const std::string expected = "expected a state index in [0, " + std::to_string(n - 1) + "] or a state name (the dynamics '" +
                               dyn.type() + "' has the states " + join(names) + ") or null";
  if (!e.is_scalar()) e.fail(expected);
  const std::string text = e.text();
  for (int i = 0; i < n; ++i)
    if (names[static_cast<std::size_t>(i)] == text) return i;
  char* end = nullptr;
  const long i = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || i < 0 || i >= n) e.fail(expected);
  return static_cast<int>(i);
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
  if (!pos.is_sequence() || (pos.size() != 2 && pos.size() != 3))
    pos.fail("expected 2 entries [x, y] (the plane) or 3 [x, y, z] (space): state indices (0-based) or names, "
             "or null for a fixed coordinate");
  const std::size_t D = pos.size();
  ws.index.assign(D, 0);
  ws.offset.assign(D, 0.0);
  for (std::size_t c = 0; c < D; ++c) {
    Field e = pos[c];
    if (!e.present()) {
      ws.index[c] = -1;
      continue;
    }
    ws.index[c] = position_index(e, dyn);
  }
  if (f.child("offset").present()) {
    const Eigen::VectorXd o = f.child("offset").vector(static_cast<int>(D), D == 2 ? "a point in the plane" : "a point in space (as many entries as position)");
    for (std::size_t c = 0; c < D; ++c) ws.offset[c] = o[static_cast<int>(c)];
  }
  return ws;
}

void validate_agent(const AgentSpec& a, const Field& x0f, const Field& radiusf, const Field& goalf, double bounds_clearance) {
  const auto names = a.dynamics->state_names();
  const auto& ix = a.workspace.index;
  for (int i = 0; i < a.n(); ++i) {
    const std::string coord = "'" + names[i] + "'";
    const std::size_t si = static_cast<std::size_t>(i);
    const double lo = a.state_bounds.lo[i], hi = a.state_bounds.hi[i];
    // Bounds the body's clearance pulled in are named as such: the file's numbers differ.
    const bool pulled = bounds_clearance > 0 && a.workspace.linear() && std::find(ix.begin(), ix.end(), i) != ix.end();
    const std::string in_bounds = "[" + number_text(lo) + ", " + number_text(hi) + "]" +
                                  (pulled ? " (the state bounds less the body's clearance " + number_text(bounds_clearance) + ")" : "");
    switch (agent_defect(a, i)) {
      case AgentDefect::None:
      case AgentDefect::AngleTubeTooWide:  // located at eps by check_periodic_eps, which runs first
        break;
      case AgentDefect::X0OutsideBounds:
        x0f[si].fail("x0 = " + number_text(a.x0[i]) + " in " + coord + " lies outside " + (pulled ? "" : "the state bounds ") + in_bounds);
      case AgentDefect::TubeOutsideBounds:
        x0f[si].fail("the tube around x0 leaves the state bounds in " + coord + ": x0 +- eps = [" +
                     number_text(a.x0[i] - a.tube.eps[i]) + ", " + number_text(a.x0[i] + a.tube.eps[i]) +
                     "] is not inside " + in_bounds);
      case AgentDefect::InitialSetOutsideTube:
        (radiusf.is_sequence() ? radiusf[si] : radiusf).fail("the stated initial set x0 +- " + number_text(a.x0_half(i)) + " in " + coord +
                     " does not fit strictly inside the tube x0 +- eps = x0 +- " + number_text(a.tube.eps[i]) +
                     "; give a smaller x0_radius or a larger eps");
      case AgentDefect::GoalEmpty:
        goalf.fail("the goal shrunk by eps is empty in " + coord + ": [" + number_text(a.goal.lo[i]) + " + " +
                   number_text(a.tube.eps[i]) + ", " + number_text(a.goal.hi[i]) + " - " + number_text(a.tube.eps[i]) +
                   "] = [" + number_text(a.goal.lo[i] + a.tube.eps[i]) + ", " +
                   number_text(a.goal.hi[i] - a.tube.eps[i]) + "]; enlarge the goal or reduce eps");
      case AgentDefect::GoalOutsideBounds:
        goalf.fail("the goal [" + number_text(a.goal.lo[i]) + ", " + number_text(a.goal.hi[i]) + "] in " + coord +
                   " lies outside " + (pulled ? "" : "the state bounds ") + in_bounds);
      case AgentDefect::GoalUnreachable:
        goalf.fail("no eps-robust final state in " + coord + ": the goal shrunk by eps [" +
                   number_text(a.goal.lo[i] + a.tube.eps[i]) + ", " + number_text(a.goal.hi[i] - a.tube.eps[i]) +
                   "] and the state bounds shrunk by eps [" + number_text(lo + a.tube.eps[i]) + ", " +
                   number_text(hi - a.tube.eps[i]) +
                   "] do not overlap; move the goal inside the state bounds or reduce eps");
    }
  }
}

void check_field_finite(const AgentSpec& a, const Field& dynamics) {
  const int n = a.n();
  const Eigen::VectorXd u = a.input_bounds.center();
  const auto names = a.dynamics->state_names();
  const std::pair<const char*, Eigen::VectorXd> points[] = {{"x0", a.x0}, {"the goal's centre", a.goal.center()}};
  for (const auto& [where, x] : points) {
    Eigen::VectorXd dx = Eigen::VectorXd::Zero(n);
    a.dynamics->field(x.data(), u.data(), dx.data());
    for (int i = 0; i < n; ++i) {
      if (std::isfinite(dx[i])) continue;
      const std::string name = i < static_cast<int>(names.size()) ? names[i] : std::to_string(i);
      const std::string why = "the vector field is not finite at " + std::string(where) + " " + list_text(x) +
                              " with the input at the centre of U " + list_text(u) + ": d" + name + "/dt = " +
                              number_text(dx[i]) + " (a division by zero, or log or sqrt of a negative number?)";
      if (dynamics.is_map() && dynamics.child("field").child(name).present()) dynamics.child("field").child(name).fail(why);
      dynamics.fail(why);
    }
  }
}

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

AgentTrackers resolve_tracker(AgentSpec& a, const TrackerRequest& req, TrackerInstances& trackers,
                              const PluginRegistry& reg, const Problem& pb, const MemoryBudget& budget, const Field& af,
                              const Field& defaults) {
  const AssessRequest ask{pb.horizon, pb.tau, budget};
  AgentTrackers out;
  out.automatic = req.automatic;
  if (!req.automatic) {
    const TrackerAssessment as = assess_tracker(trackers, req.choice, a, ask);
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
    const TrackerAssessment as = assess_tracker(trackers, {name, {}}, a, ask);
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

}  // namespace marsyn::loader
