#include "stage_fields.hpp"

#include "periodic_fields.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "agent_fields.hpp"
#include "field_text.hpp"
#include "marsyn/core/problem/input_limits.hpp"
#include "scene_fields.hpp"

namespace marsyn::loader {

namespace {

enum class Round { Up, Down };

// A time as steps (an integer) or seconds ("2.5 s", "2.5s"); seconds become the first knot at or
// after them (Up) or the last at or before them (Down).
int read_steps(const Field& f, double tau, Round round, const std::string& what) {
  const std::string expected = "expected " + what + " as a number of steps (an integer) or in seconds, e.g. '2.5 s'";
  if (!f.is_scalar()) f.fail(expected);
  std::string s = f.text();
  const bool seconds = !s.empty() && s.back() == 's';
  if (!seconds) {
    std::size_t used = 0;
    long k = -1;
    try {
      k = std::stol(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != s.size()) f.fail(expected + ", got '" + s + "'");
    if (k < 0 || k > kMaxHorizon)
      f.fail("expected " + what + " in [0, " + std::to_string(kMaxHorizon) + "] steps, got " + s);
    return static_cast<int>(k);
  }
  s.pop_back();
  while (!s.empty() && s.back() == ' ') s.pop_back();
  double t = 0.0;
  std::size_t used = 0;
  try {
    t = std::stod(s, &used);
  } catch (const std::exception&) {
    f.fail(expected + ", got '" + f.text() + "'");
  }
  if (used != s.size() || !std::isfinite(t) || t < 0) f.fail(expected + " (a finite time >= 0), got '" + f.text() + "'");
  const double k = t / tau;
  // Within a millionth of a step of a knot counts as that knot: 0.3 s / 0.1 s is not 2.9999.
  const double r = std::round(k);
  const double v = std::abs(k - r) < 1e-6 ? r : round == Round::Up ? std::ceil(k) : std::floor(k);
  if (v > static_cast<double>(kMaxHorizon))
    f.fail("expected at most " + std::to_string(kMaxHorizon) + " steps (" + number_text(kMaxHorizon * tau) +
           " s), got '" + f.text() + "'");
  return static_cast<int>(v);
}

// Is the polygon, shrunk by the eps box of the workspace point (edge e: by |n_e| . r), non-empty?
// Its vertices are among the pairwise intersections of the shifted edge lines.
bool shrunk_polygon_nonempty(const std::vector<Eigen::Vector2d>& P, const Eigen::Vector2d& r) {
  const std::size_t V = P.size();
  std::vector<Eigen::Vector2d> n(V);
  std::vector<double> b(V);
  for (std::size_t i = 0; i < V; ++i) {
    const Eigen::Vector2d e = P[(i + 1) % V] - P[i];
    n[i] = Eigen::Vector2d(e.y(), -e.x()) / e.norm();
    b[i] = n[i].dot(P[i]) - std::abs(n[i].x()) * r.x() - std::abs(n[i].y()) * r.y();
  }
  for (std::size_t i = 0; i < V; ++i)
    for (std::size_t j = i + 1; j < V; ++j) {
      const double det = n[i].x() * n[j].y() - n[i].y() * n[j].x();
      if (std::abs(det) < 1e-14) continue;
      const Eigen::Vector2d p((b[i] * n[j].y() - b[j] * n[i].y()) / det, (n[i].x() * b[j] - n[j].x() * b[i]) / det);
      bool in = true;
      for (std::size_t e = 0; e < V && in; ++e) in = n[e].dot(p) <= b[e] + 1e-12;
      if (in) return true;
    }
  return false;
}

// The fewest knots a's stages need (each after the previous one's dwell, in its window, the
// goal's knot after the last): the horizon must be at least this. -1 with `why` when a window
// cannot be met at any horizon.
int shortest_mission(const AgentSpec& a, std::string* why) {
  int end = 0;
  for (const auto& st : a.stages) {
    const int k = std::max({1, st.not_before, end + 1});
    if (st.by >= 0 && k > st.by) {
      if (why)
        *why = "stage '" + st.name + "' cannot be visited by step " + std::to_string(st.by) +
               ": the earliest knot after the stages before it is " + std::to_string(k);
      return -1;
    }
    end = k + st.dwell;
  }
  return end + 1;
}

MissionStage read_stage(const Field& f, std::size_t index, const AgentSpec& a, double tau) {
  f.expect_map();
  f.allow_only({"name", "region", "not_before", "by", "dwell", "team", "avoid", "avoid_after"});
  MissionStage st;
  st.name = "stage" + std::to_string(index + 1);
  if (Field nf = f.child("name"); nf.present()) {
    st.name = nf.text();
    if (const std::string why = name_defect(st.name); !why.empty()) nf.fail(why);
  }
  read_stage_region(f.required("region"), a, st);
  if (Field w = f.child("not_before"); w.present()) st.not_before = std::max(1, read_steps(w, tau, Round::Up, "the earliest visit"));
  if (Field w = f.child("by"); w.present()) {
    st.by = read_steps(w, tau, Round::Down, "the latest visit");
    if (st.by < 1) w.fail("expected a latest visit at step 1 or later (step 0 is the start, which no plan can move), got " + std::to_string(st.by));
    if (st.by < st.not_before)
      w.fail("the window is empty: 'by' (step " + std::to_string(st.by) + ") is before 'not_before' (step " +
             std::to_string(st.not_before) + ")");
  }
  if (Field w = f.child("dwell"); w.present()) st.dwell = read_steps(w, tau, Round::Up, "the dwell");
  if (Field t = f.child("team"); t.present()) {
    st.team = t.text();
    if (const std::string why = name_defect(st.team); !why.empty()) t.fail(why);
  }
  return st;
}

}  // namespace

void read_stage_region(const Field& rf, const AgentSpec& a, MissionStage& st) {
  const int n = a.n();
  const auto& names = a.dynamics->state_names();
  rf.expect_map();
  if (rf.child("polygon").present()) {
    rf.allow_only({"polygon"});
    if (!a.workspace.linear())
      rf.child("polygon").fail("a polygon region needs a linear workspace map ({position: [i, j]}); agent '" + a.name +
                               "' uses the footprint '" + a.workspace.footprint_name + "': give a box in the state instead");
    st.polygon = read_convex_polygon(rf.child("polygon"));
    Eigen::Vector2d r(0.0, 0.0);
    for (int c = 0; c < 2; ++c)
      if (a.workspace.index[c] >= 0) r[c] = a.tube.eps[a.workspace.index[c]];
    if (!shrunk_polygon_nonempty(st.polygon, r))
      rf.child("polygon").fail("the polygon shrunk by eps (" + number_text(r.x()) + ", " + number_text(r.y()) +
                               " in the workspace) is empty: no eps-robust visit exists; enlarge it or reduce eps");
  } else {
    const std::string sn = "a box in the state of '" + a.dynamics_type + "', which has " + std::to_string(n) +
                           " states; or {polygon: [[x, y], ...]} in the workspace";
    st.box = read_box_any(rf, n, sn, std::vector<bool>(static_cast<std::size_t>(n), true), "");
    lift_box(st.box, a);  // `any` is the state bounds; an angle's arc the branch nearest x0
    for (int c = 0; c < n; ++c) {
      const std::string coord = "'" + names[c] + "'";
      const double lo = std::max(st.box.lo[c], a.state_bounds.lo[c]) + a.tube.eps[c];
      const double hi = std::min(st.box.hi[c], a.state_bounds.hi[c]) - a.tube.eps[c];
      if (lo > hi)
        rf.fail("the region in " + coord + " [" + number_text(st.box.lo[c]) + ", " + number_text(st.box.hi[c]) +
                "], within the state bounds and shrunk by eps " + number_text(a.tube.eps[c]) + ", is empty ([" +
                number_text(lo) + ", " + number_text(hi) + "]): no eps-robust visit exists; enlarge it or reduce eps");
    }
  }
}

std::vector<MissionStage> read_stages(const Field& f, const AgentSpec& a, double tau, int horizon) {
  if (!f.is_sequence()) f.fail("expected a list of stages [{region: ..., by: ..., dwell: ...}, ...]");
  const auto items = f.items();
  if (items.size() > 1000) f.fail("expected at most 1000 stages, got " + std::to_string(items.size()));
  std::vector<MissionStage> out;
  std::map<std::string, std::size_t> seen;
  for (std::size_t s = 0; s < items.size(); ++s) {
    out.push_back(read_stage(items[s], s, a, tau));
    if (auto [it, fresh] = seen.try_emplace(out.back().name, s); !fresh)
      (items[s].child("name").present() ? items[s].child("name") : items[s])
          .fail("duplicate stage name '" + out.back().name + "' (also stages[" + std::to_string(it->second) + "])");
  }
  AgentSpec probe = a;
  for (std::size_t s = 0; s < items.size(); ++s) {
    probe.stages.assign(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(s + 1));
    std::string why;
    if (shortest_mission(probe, &why) < 0)
      (items[s].child("by").present() ? items[s].child("by") : items[s]).fail(why);
  }
  check_mission_horizon(f, a, out, horizon);
  return out;
}

void check_mission_horizon(const Field& f, const AgentSpec& a, const std::vector<MissionStage>& stages, int horizon) {
  AgentSpec probe = a;
  probe.stages = stages;
  const int need = shortest_mission(probe, nullptr);
  if (need > horizon)
    f.fail("the stages need a horizon of at least " + std::to_string(need) + " steps (windows, dwells and one step "
           "per visit, then the goal), but 'horizon' is " + std::to_string(horizon));
}

void check_teams(const Problem& pb, const std::vector<Field>& stage_fields) {
  std::map<std::string, std::vector<int>> members;  // team -> agents
  std::map<std::string, std::pair<int, int>> first;  // team -> (agent, stage) where written first
  for (int i = 0; i < static_cast<int>(pb.agents.size()); ++i)
    for (int s = 0; s < static_cast<int>(pb.agents[i].stages.size()); ++s) {
      const std::string& t = pb.agents[i].stages[s].team;
      if (t.empty()) continue;
      auto& m = members[t];
      if (std::find(m.begin(), m.end(), i) != m.end())
        stage_fields[i][static_cast<std::size_t>(s)].child("team").fail(
            "agent '" + pb.agents[i].name + "' has two stages in team '" + t + "'; a team stage is one visit per agent");
      m.push_back(i);
      first.try_emplace(t, i, s);
    }
  for (const auto& [t, m] : members)
    if (m.size() < 2) {
      const auto [i, s] = first[t];
      stage_fields[i][static_cast<std::size_t>(s)].child("team").fail(
          "team '" + t + "' has only one member (agent '" + pb.agents[i].name +
          "'); a team stage (rendezvous) names stages of at least two agents");
    }
}

namespace {

// A stage's `avoid` or `avoid_after`: names of obstacles declared with `scope: stages`.
std::vector<int> read_obstacle_names(const Field& f, const std::vector<Obstacle>& obstacles) {
  std::vector<std::string> names, staged;
  for (const auto& o : obstacles) {
    names.push_back(o.name);
    if (o.staged) staged.push_back(o.name);
  }
  if (!f.is_sequence()) f.fail("expected a list of obstacle names declared with 'scope: stages', e.g. [door]");
  std::vector<int> out;
  for (const Field& item : f.items()) {
    if (!item.is_scalar()) item.fail("expected an obstacle name");
    const std::string name = item.text();
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) {
      const std::string near = yaml::nearest(name, names);
      item.fail("unknown obstacle '" + name + "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)") +
                (names.empty() ? "; the problem has no obstacles" : "; obstacles: " + join(names)));
    }
    const int o = static_cast<int>(it - names.begin());
    if (!obstacles[static_cast<std::size_t>(o)].staged)
      item.fail("obstacle '" + name + "' binds every agent at every step already; declare it with 'scope: stages' to have "
                "it bind only on the stages that name it" +
                (staged.empty() ? std::string() : " (obstacles with 'scope: stages': " + join(staged) + ")"));
    if (std::find(out.begin(), out.end(), o) != out.end()) item.fail("obstacle '" + name + "' is listed twice");
    out.push_back(o);
  }
  return out;
}

}  // namespace

void read_stage_obstacles(Problem& pb, const std::vector<Field>& stage_fields, const Field& obstacles_field) {
  std::vector<bool> named(pb.obstacles.size(), false);
  for (std::size_t i = 0; i < pb.agents.size() && i < stage_fields.size(); ++i) {
    if (!stage_fields[i].present()) continue;
    const auto items = stage_fields[i].items();
    auto& stages = pb.agents[i].stages;
    for (std::size_t s = 0; s < stages.size() && s < items.size(); ++s) {
      if (Field f = items[s].child("avoid"); f.present()) stages[s].avoid = read_obstacle_names(f, pb.obstacles);
      if (Field f = items[s].child("avoid_after"); f.present()) stages[s].avoid_after = read_obstacle_names(f, pb.obstacles);
      for (int o : stages[s].avoid) named[static_cast<std::size_t>(o)] = true;
      for (int o : stages[s].avoid_after) named[static_cast<std::size_t>(o)] = true;
    }
  }
  if (!obstacles_field.present()) return;
  const auto items = obstacles_field.items();
  for (std::size_t o = 0; o < pb.obstacles.size() && o < items.size(); ++o)
    if (pb.obstacles[o].staged && !named[o])
      items[o].child("scope").fail("obstacle '" + pb.obstacles[o].name + "' has 'scope: stages' but no stage names it "
                                   "in 'avoid' or 'avoid_after', so it would bind nobody: name it in a stage, or remove "
                                   "the scope to have it bind every agent");
}

}  // namespace marsyn::loader
