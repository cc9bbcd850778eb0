#include <algorithm>
#include <cmath>

#include "marsyn/core/planning/mission.hpp"
#include "marsyn/core/report/report_html.hpp"
#include "marsyn/scalar.hpp"

namespace marsyn {
namespace {

// The drawing's axes: the top view x-y (the plane's only one), or a 3-D workspace's side view x-z
// and front view y-z.
struct View {
  int u = 0, v = 1;
};

// Sound workspace box of a state box in the view's axes: interval evaluation of the agent's
// workspace map.
std::array<double, 4> workspace_box(const AgentSpec& a, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, View w) {
  std::vector<Interval> x(a.n());
  for (int i = 0; i < a.n(); ++i) x[i] = Interval(lo[i], hi[i]);
  Interval p[kMaxWorkspaceDim];
  workspace_point3<Interval>(*a.dynamics, a.workspace, x.data(), p);
  return {p[w.u].lower(), p[w.v].lower(), p[w.u].upper(), p[w.v].upper()};
}

std::array<double, 2> point_in(const AgentSpec& a, const double* x, View w) {
  double p[kMaxWorkspaceDim];
  workspace_point3<double>(*a.dynamics, a.workspace, x, p);
  return {p[w.u], p[w.v]};
}

// An obstacle as the view sees it: its polygon from above; from the side (or the front) the
// rectangle of its x (y) extent and heights (a full-height one drawn 1000 units high).
nlohmann::json obstacle_outline(const Obstacle& o, View w) {
  nlohmann::json v = nlohmann::json::array();
  if (w.v != 2) {
    for (const auto& p : o.vertices) v.push_back({p.x(), p.y()});
    return v;
  }
  double lo = 1e300, hi = -1e300;
  for (const auto& p : o.vertices) {
    lo = std::min(lo, p[w.u]);
    hi = std::max(hi, p[w.u]);
  }
  const double zl = std::max(o.z_lo, -1e3), zh = std::min(o.z_hi, 1e3);
  return {{lo, zl}, {hi, zl}, {hi, zh}, {lo, zh}};
}

nlohmann::json round4(double v) { return std::round(v * 1e4) / 1e4; }

}  // namespace

// `pb` is the problem at the plan's visit knots (planning::with_visits, solve_outputs.cpp), so the
// schedule and the staged obstacles' windows computed from it here are the plan's.
namespace {

nlohmann::json obstacles_json(const Problem& pb, int horizon, View view) {
  using nlohmann::json;
  json obstacles = json::array();
  const planning::ObstacleWindows windows(pb, horizon);
  for (std::size_t oi = 0; oi < pb.obstacles.size(); ++oi) {
    const Obstacle& o = pb.obstacles[oi];
    json ob = {{"name", o.name}, {"vertices", obstacle_outline(o, view)}};
    if (o.staged) {
      // [from, to] knot ranges where it binds some agent: drawn solid there, outlined elsewhere.
      json binds = json::array();
      for (std::size_t i = 0; i < pb.agents.size(); ++i)
        for (int k = 0; k <= horizon; ++k) {
          if (!windows.binds(static_cast<int>(i), static_cast<int>(oi), {k, false})) continue;
          int e = k;
          while (e < horizon && windows.binds(static_cast<int>(i), static_cast<int>(oi), {e + 1, false})) ++e;
          binds.push_back({{"agent", pb.agents[i].name}, {"from", k}, {"to", e}});
          k = e;
        }
      ob["binds"] = binds;
    }
    obstacles.push_back(ob);
  }
  return obstacles;
}

// Agent i's mission stages: each region's outline, its visit knot (at the nominal's horizon T)
// and dwell.
nlohmann::json stages_json(const Problem& pb, std::size_t i, int T, View view) {
  using nlohmann::json;
  const AgentSpec& a = pb.agents[i];
  const planning::MissionSchedule sched = planning::schedule_missions(pb, T);
  json stages = json::array();
  for (std::size_t s = 0; s < a.stages.size(); ++s) {
    const MissionStage& st = a.stages[s];
    json v = json::array();
    if (st.is_polygon()) {
      Obstacle region;  // a region of the plane: from the side, its x extent at every height
      region.vertices = st.polygon;
      v = obstacle_outline(region, view);
    } else {
      const auto b = workspace_box(a, st.box.lo, st.box.hi, view);
      v = {{b[0], b[1]}, {b[2], b[1]}, {b[2], b[3]}, {b[0], b[3]}};
    }
    stages.push_back({{"name", st.name}, {"order", s + 1}, {"vertices", v}, {"visit", sched.visit[i][s]}, {"dwell", st.dwell}});
  }
  return stages;
}

nlohmann::json agent_scene_json(const Problem& pb, std::size_t i, const std::vector<NominalTrajectory>& nominal,
                                const std::vector<const std::vector<PeriodEnclosure>*>& enc, View view) {
  using nlohmann::json;
  const AgentSpec& a = pb.agents[i];
  json ag;
  ag["name"] = a.name;
  if (a.radius > 0) ag["radius"] = a.radius;
  const auto g = workspace_box(a, a.goal.lo, a.goal.hi, view);
  ag["goal"] = {g[0], g[1], g[2], g[3]};
  json tube = json::array(), path = json::array();
  if (i < nominal.size())
    for (const auto& x : nominal[i].x) {
      const auto b = workspace_box(a, x - a.tube.eps, x + a.tube.eps, view);
      tube.push_back({round4(b[0]), round4(b[1]), round4(b[2]), round4(b[3])});
      const auto p = point_in(a, x.data(), view);
      path.push_back({round4(p[0]), round4(p[1])});
    }
  ag["tube"] = tube;
  ag["nominal"] = path;
  // Further bodies (a tractor's cart): each one's point along the nominal, drawn with its radius.
  json bodies = json::array();
  for (int b = static_cast<int>(pb.agents.size()); b < pb.body_count(); ++b) {
    if (pb.body_agent(b) != static_cast<int>(i) || i >= nominal.size()) continue;
    const AgentSpec& body = pb.body_spec(b);
    json pts = json::array();
    for (const auto& x : nominal[i].x) {
      const auto p = point_in(body, x.data(), view);
      pts.push_back({round4(p[0]), round4(p[1])});
    }
    bodies.push_back({{"name", pb.extra_bodies[static_cast<std::size_t>(b) - pb.agents.size()].body}, {"radius", body.radius},
                      {"nominal", pts}});
  }
  if (!bodies.empty()) ag["bodies"] = bodies;
  // [step][part] = workspace box of the closed loop during that part of the period.
  json periods = json::array();
  if (i < enc.size() && enc[i])
    for (const PeriodEnclosure& e : *enc[i]) {
      while (static_cast<int>(periods.size()) <= e.step) periods.push_back(json::array());
      if (e.workspace.dim() <= view.v) continue;  // a tracker's planar enclosure has no side view
      periods[static_cast<size_t>(e.step)].push_back({round4(e.workspace.lo[view.u]), round4(e.workspace.lo[view.v]),
                                                       round4(e.workspace.hi[view.u]), round4(e.workspace.hi[view.v])});
    }
  ag["enclosures"] = periods;
  if (!a.stages.empty())
    ag["stages"] = stages_json(pb, i, i < nominal.size() ? static_cast<int>(nominal[i].u.size()) : pb.horizon, view);
  return ag;
}

// The closed-loop runs the verification kept: margins per step and dense in time, and each
// agent's path.
nlohmann::json runs_json(const Problem& pb, const VerificationReport* ver, View view) {
  using nlohmann::json;
  json runs = json::array();
  if (!ver) return runs;
  for (const auto& kept : ver->kept) {
    json r;
    r["label"] = kept.label;
    r["satisfied"] = kept.spec.satisfied;
    r["min_margin"] = kept.spec.min_margin;
    r["worst"] = kept.spec.worst;
    json margins = json::array();
    for (const auto& m : kept.spec.per_step) margins.push_back(round4(std::max(-1e3, std::min(1e3, m.min()))));
    r["margin"] = margins;
    // Dense in time (every integration substep): the continuous-time margin curve.
    json dense = json::array();
    for (const auto& m : kept.dense) dense.push_back(round4(std::max(-1e3, std::min(1e3, m.min()))));
    r["dense"] = dense;
    json pts = json::array();  // [agent][step] = [x, y]
    for (std::size_t i = 0; i < pb.agents.size(); ++i) {
      json track = json::array();
      const int off = ProductLayout(pb).state[i];
      for (const auto& x : kept.states) {
        const auto p = point_in(pb.agents[i], x.data() + off, view);
        track.push_back({round4(p[0]), round4(p[1])});
      }
      pts.push_back(track);
    }
    r["points"] = pts;
    runs.push_back(r);
  }
  return runs;
}

nlohmann::json view_scene(const Problem& pb, const std::vector<NominalTrajectory>& nominal, const VerificationReport* ver,
                          const std::vector<const std::vector<PeriodEnclosure>*>& enc, View view) {
  using nlohmann::json;
  json scene;
  scene["axes"] = {std::string(1, "xyz"[view.u]), std::string(1, "xyz"[view.v])};
  scene["tau"] = pb.tau;
  scene["delta"] = pb.delta;
  scene["delta_obstacles"] = pb.obstacle_delta();
  scene["norm"] = pb.delta_norm == Norm::Inf ? "inf" : "2";
  const int horizon = !nominal.empty() && !nominal.front().u.empty() ? static_cast<int>(nominal.front().u.size()) : pb.horizon;
  scene["obstacles"] = obstacles_json(pb, horizon, view);
  json agents = json::array();
  for (std::size_t i = 0; i < pb.agents.size(); ++i) agents.push_back(agent_scene_json(pb, i, nominal, enc, view));
  scene["agents"] = agents;
  scene["runs"] = runs_json(pb, ver, view);
  return scene;
}

}  // namespace

nlohmann::json report_scene(const Problem& pb, const std::vector<NominalTrajectory>& nominal,
                            const VerificationReport* ver, const std::vector<const std::vector<PeriodEnclosure>*>& enc) {
  nlohmann::json scene = view_scene(pb, nominal, ver, enc, View{0, 1});
  // A 3-D workspace gets a side view (x-z) and a front view (y-z) next to the top view: heights
  // are what a prism or a window constrains, and a window in a wall across x shows only from the
  // front.
  if (pb.workspace_dim == 3) {
    scene["side"] = view_scene(pb, nominal, ver, enc, View{0, 2});
    scene["front"] = view_scene(pb, nominal, ver, enc, View{1, 2});
  }
  return scene;
}

}  // namespace marsyn
