#include "marsyn/core/problem/problem_loader.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include <climits>

#include "marsyn/core/planning/workspace_gaps.hpp"
#include "marsyn/core/problem/agent_checks.hpp"
#include "marsyn/directed_rounding.hpp"
#include "marsyn/core/problem/input_limits.hpp"
#include "marsyn/core/problem/tracker_assessment.hpp"
#include "marsyn/core/problem/tracker_fields.hpp"
#include "agent_fields.hpp"
#include "periodic_fields.hpp"
#include "disturbance_fields.hpp"
#include "marsyn/core/problem/auto_tube.hpp"
#include "tube_fields.hpp"
#include "equations/equation_yaml.hpp"
#include "field_text.hpp"
#include "plugin_fields.hpp"
#include "scene_fields.hpp"
#include "ltl_fields.hpp"
#include "stage_fields.hpp"
#include "yaml_reader.hpp"

namespace fs = std::filesystem;

namespace marsyn {
namespace {

using namespace loader;

const std::vector<std::string> kTopKeys = {
    "name",  "description", "tau",     "horizon",      "rk4_substeps", "delta",     "delta_norm",
    "pairwise_collision", "guarantee", "planner", "tracker", "collision", "plugin_paths", "defaults", "agents", "obstacles",
    "formation", "search", "regions"};
const std::vector<std::string> kAgentKeys = {"name",         "dynamics",     "x0",          "goal",
                                             "state_bounds", "input_bounds", "disturbance", "eps",
                                             "workspace",    "tracker",      "stages",      "ltl",
                                             "x0_radius",    "radius",       "bodies"};

// An agent's keys: core's, with the installed trackers' own fields (abcd: eta_x, eta_u) after eps.
std::vector<std::string> agent_keys(const std::vector<AgentFieldSpec>& fields) {
  std::vector<std::string> keys = kAgentKeys;
  auto at = std::find(keys.begin(), keys.end(), "eps") + 1;
  for (const auto& f : fields) at = keys.insert(at, f.name) + 1;
  return keys;
}

// plugin_paths (relative to the file's folder) and the registry they open; a library that failed
// to load is an error at its entry.
void read_plugin_paths(const Field& top, const std::string& path, LoadedProblem& out) {
  const fs::path base = fs::path(path).parent_path();
  std::vector<std::string> plugin_paths;
  if (Field pp = top.child("plugin_paths"); pp.present()) {
    for (const auto& item : pp.items()) {
      fs::path p = item.text();
      if (p.is_relative()) p = base / p;
      plugin_paths.push_back(p.lexically_normal().string());
    }
  }
  out.problem.plugin_paths = plugin_paths;
  out.registry = std::make_shared<PluginRegistry>(plugin_paths);
  for (const auto& prob : out.registry->problems()) {
    if (!prob.explicit_path) continue;
    Field pp = top.child("plugin_paths");
    for (std::size_t i = 0; i < plugin_paths.size(); ++i)
      if (prob.library_path.rfind(plugin_paths[i], 0) == 0) pp[i].fail("plugin library " + prob.library_path + " " + prob.reason);
    pp.fail("plugin library " + prob.library_path + " " + prob.reason);
  }
}

// tau, search, horizon, rk4_substeps, delta, delta_norm, pairwise_collision, guarantee.
void read_timing_and_norms(const Field& top, LoadedProblem& out) {
  Problem& pb = out.problem;
  pb.tau = top.required("tau").positive();
  if (Field search = top.child("search"); search.present()) {
    search.expect_map();
    search.allow_only({"time_limit", "planner_fallback"});
    if (Field t = search.child("time_limit"); t.present()) out.search_time_limit_s = t.positive();
    if (Field f = search.child("planner_fallback"); f.present()) out.planner_fallback = f.boolean();
  }
  pb.horizon = static_cast<int>(top.required("horizon").integer_in(1, kMaxHorizon, "steps"));
  if (Field f = top.child("rk4_substeps"); f.present())
    pb.rk4_substeps = static_cast<int>(f.integer_in(1, kMaxRk4Substeps, "RK4 substeps per step"));
  if (Field f = top.child("delta"); f.present()) {
    if (f.is_map()) {  // clearance by kind: between agents, to obstacles, to the state bounds
      f.allow_only({"agents", "obstacles", "bounds"});
      pb.delta = f.required("agents").non_negative();
      pb.delta_obstacles = f.required("obstacles").non_negative();
      if (Field b = f.child("bounds"); b.present()) pb.delta_bounds = b.non_negative();
    } else {
      pb.delta = f.non_negative();
    }
  }
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
}

// What reading the agents one by one carries from one to the next and on to the checks after.
struct AgentsRead {
  const Field& defaults;
  const Field& regions;
  bool spatial;  // obstacles, collisions or a formation: every agent needs a workspace point
  const TrackerRequest& top_tracker;
  TrackerInstances& tracker_instances;
  const std::vector<AgentFieldSpec>& tracker_fields;  // the installed trackers' own agent fields
  const std::vector<std::string>& agent_keys;
  std::map<std::string, std::size_t> seen;  // names so far, with their index
  std::vector<Field> x0_fields, stage_fields, ltl_fields;
  std::vector<Field> agent_fields;           // per agent: its own mapping (for a second look at its tracker)
  std::vector<TrackerRequest> tracker_requests;
  std::vector<std::vector<LtlAvoid>> ltl_avoid;
};

// A plugin name, or equations written in the file (core/src/problem/equations, issue 15).
void read_dynamics(const Field& af, const Field& defaults, const PluginRegistry& registry, AgentSpec& a) {
  const Field dyn_field = agent_required(af, defaults, "dynamics");
  if (equations::is_equation_model(dyn_field, defaults.child("dynamics"))) {
    a.dynamics = equations::load_equation_dynamics(dyn_field, defaults.child("dynamics"));
    a.dynamics_type = a.dynamics->type();
  } else {
    const PluginField dyn = read_plugin_field(dyn_field, "type");
    a.dynamics_type = dyn.name;
    a.dynamics = create_plugin<Dynamics>(registry, dyn).first;
  }
}

// The mission, as `stages` or as `ltl` (docs/tasks.md): the agent's own field before the
// defaults' one; both in one block is an error.
void read_mission(const Field& af, const Problem& pb, AgentSpec& a, AgentsRead& r) {
  for (const Field& block : {af, r.defaults})
    if (block.child("stages").present() && block.child("ltl").present())
      block.child("ltl").fail("give the mission either as 'stages' or as 'ltl', not both");
  const bool own = af.child("stages").present() || af.child("ltl").present();
  const Field& mission_block = own ? af : r.defaults;
  r.stage_fields.push_back(mission_block.child("stages"));
  r.ltl_fields.push_back(mission_block.child("ltl"));
  r.ltl_avoid.emplace_back();
  if (r.stage_fields.back().present()) a.stages = read_stages(r.stage_fields.back(), a, pb.tau, pb.horizon);
  if (r.ltl_fields.back().present()) {
    LtlMission m = read_ltl(r.ltl_fields.back(), r.regions, a, pb.horizon);
    a.stages = std::move(m.stages);
    r.ltl_avoid.back() = std::move(m.avoid);
  }
}

// The agent's workspace point: given, or the plane at its states x and y by default. One
// workspace dimension for the team (the first agent's).
void read_agent_workspace(const Field& af, const Field& defaults, bool spatial, Problem& pb, AgentSpec& a) {
  const int n = a.dynamics->state_dim();
  // With `bodies`, the first body's map is the agent's workspace point.
  const Field bodies = agent_field(af, defaults, "bodies");
  if (bodies.present()) {
    for (const char* key : {"workspace", "radius"}) {
      if (af.child("bodies").present() ? af.child(key).present() : (defaults.child("bodies").present() && defaults.child(key).present()))
        (af.child("bodies").present() ? af.child(key) : defaults.child(key))
            .fail(std::string("give the agent's ") + key + " in its first body of 'bodies', not beside it");
      // The defaults' bodies would silently replace this agent's own point or radius.
      if (!af.child("bodies").present() && af.child(key).present())
        af.child(key).fail(std::string("the defaults give 'bodies', which would replace this agent's ") + key +
                           "; give this agent its own 'bodies' with it in the first body");
    }
    if (!bodies.is_sequence())
      bodies.fail("expected a list of bodies, each {workspace: {...}, radius: r, name: n}, the first the agent's own point");
    if (bodies.size() == 0) bodies.fail("expected at least one body: the agent's own point, {workspace: {...}, radius: r}");
    bodies[0].expect_map();
    bodies[0].allow_only({"name", "workspace", "radius"});
  }
  if (Field ws = bodies.present() ? bodies[0].required("workspace") : agent_field(af, defaults, "workspace"); ws.present()) {
    a.workspace = read_workspace(ws, *a.dynamics);
    // One workspace for the team: the first agent's dimension, every other agent's the same.
    if (pb.agents.empty()) {
      pb.workspace_dim = a.workspace.dim();
    } else if (a.workspace.dim() != pb.workspace_dim) {
      const Field pos = ws.child("position").present() ? ws.child("position") : ws;
      pos.fail("agent '" + a.name + "' has a " + std::to_string(a.workspace.dim()) + "-D workspace, but '" +
               pb.agents.front().name + "' (the first agent) has a " + std::to_string(pb.workspace_dim) +
               "-D one; all agents share one workspace (give every 'position' 2 or every one 3 entries)");
    }
  } else if (spatial) {
    // A model whose states are named x and y (the unicycle, the bicycle, the quadrotor, most
    // models written as equations) is in the plane at (x, y) unless the file says otherwise: the
    // plane is conservative for a 3-D model too (a column of the workspace for each point).
    const auto names = a.dynamics->state_names();
    const auto ix = std::find(names.begin(), names.end(), "x"), iy = std::find(names.begin(), names.end(), "y");
    if (ix == names.end() || iy == names.end())
      af.fail("missing required field 'workspace' (the problem has obstacles, collisions or a formation, so "
              "each agent needs a point in the plane: {position: [i, j]} or {footprint: name}; its states have no "
              "x and y to take by default)");
    a.workspace.index = {static_cast<int>(ix - names.begin()), static_cast<int>(iy - names.begin())};
    if (pb.agents.empty()) pb.workspace_dim = 2;
    else if (pb.workspace_dim != 2)
      af.fail("missing required field 'workspace': the team's workspace is " + std::to_string(pb.workspace_dim) +
              "-D (the first agent's), and this agent's default (its states x and y) is the plane; give its 'position'");
  } else {
    a.workspace.index = {0, n > 1 ? 1 : -1};
  }
}

// The body (`radius`) and its clearance from the state bounds (`delta: {bounds: b}`): a body of a
// linear workspace map keeps b + radius inside the bounds of every state its point reads, so
// those bounds are pulled in here and every reader of X holds the body inside the given ones.
// A further body (`bodies` after the first): its map, radius and name, owned by the agent read.
struct PendingBody {
  std::string name;
  Workspace workspace;
  double radius = 0.0;
};

// `bodies` after the first: each a workspace map of the agent's state and a radius, in the team's
// workspace dimension, named uniquely within the agent.
std::vector<PendingBody> read_further_bodies(const Field& bodies, const Problem& pb, const AgentSpec& a) {
  std::vector<PendingBody> out;
  std::vector<std::string> names;
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    const Field e = bodies[k];
    e.expect_map();
    e.allow_only({"name", "workspace", "radius"});
    std::string name = "body" + std::to_string(k + 1);
    if (Field nf = e.child("name"); nf.present()) {
      name = nf.text();
      if (const std::string why = name_defect(name); !why.empty()) nf.fail(why);
      if (std::find(names.begin(), names.end(), name) != names.end()) nf.fail("duplicate body name '" + name + "' in agent " + a.name);
    }
    names.push_back(name);
    if (k == 0) continue;  // the first body is the agent's own workspace point and radius
    PendingBody b{name, read_workspace(e.required("workspace"), *a.dynamics), 0.0};
    if (b.workspace.dim() != pb.workspace_dim)
      e.child("workspace").fail("body '" + name + "' has a " + std::to_string(b.workspace.dim()) +
                                "-D workspace point, but the workspace is " + std::to_string(pb.workspace_dim) +
                                "-D (set by the first agent's first body); give every body's 'position' as many entries");
    if (Field r = e.child("radius"); r.present()) b.radius = r.non_negative();
    out.push_back(std::move(b));
  }
  return out;
}

void read_body(const Field& af, const Field& defaults, const Field& boundsf, const Problem& pb, AgentSpec& a) {
  const Field bodies = agent_field(af, defaults, "bodies");
  // Where the body is written: its radius, else its map (a fault of its clearance is located there).
  const Field radiusf = bodies.present() ? bodies[0].child("radius") : agent_field(af, defaults, "radius");
  const Field mapf = bodies.present() ? bodies[0].child("workspace") : agent_field(af, defaults, "workspace");
  if (radiusf.present()) a.radius = radiusf.non_negative();
  if (bodies.present())
    if (Field n = bodies[0].child("name"); n.present()) a.body = n.text();
  // Rounded toward a smaller X: the body stays inside the given bounds, not an ulp outside.
  const RoundToNearestScope nearest;
  const double clear = fast_detail::add_up(pb.delta_bounds, a.radius);
  if (!a.workspace.linear() && pb.delta_bounds > 0.0)
    mapf.fail("delta's bounds keep a body clear of the state bounds of the states its point reads, but agent " + a.name +
              "'s point is the footprint '" + a.workspace.footprint_name +
              "', a function of its state with no bounds of its own; give delta's bounds 0 and this agent's state "
              "bounds with the clearance it needs");
  if (!(clear > 0.0) || !a.workspace.linear()) return;
  const auto names = a.dynamics->state_names();
  std::vector<int> states;  // each state once (a map may read one state twice)
  for (int i : a.workspace.index)
    if (i >= 0 && std::find(states.begin(), states.end(), i) == states.end()) states.push_back(i);
  for (int i : states) {
    double& lo = a.state_bounds.lo[i];
    double& hi = a.state_bounds.hi[i];
    if (!(hi - lo > 2.0 * clear))
      (radiusf.present() && a.radius > 0 ? radiusf : boundsf)
          .fail("the state bounds [" + number_text(lo) + ", " + number_text(hi) + "] in '" + names[static_cast<std::size_t>(i)] +
                "' leave no room for " + a.name + "'s body: it keeps " + number_text(clear) + " from each side (delta's bounds " +
                number_text(pb.delta_bounds) + " + radius " + number_text(a.radius) + ")");
    if (std::isfinite(lo)) lo = fast_detail::add_up(lo, clear);  // an unbounded side stays unbounded
    if (std::isfinite(hi)) hi = fast_detail::sub_down(hi, clear);
  }
}

void read_agent(const Field& af, std::size_t idx, LoadedProblem& out, AgentsRead& r) {
  Problem& pb = out.problem;
  const Field& defaults = r.defaults;
  af.expect_map();
  af.allow_only(r.agent_keys);
  AgentSpec a;
  Field name = af.required("name");
  a.name = name.text();
  if (const std::string why = name_defect(a.name); !why.empty()) name.fail(why);
  if (auto it = r.seen.find(a.name); it != r.seen.end())
    name.fail("duplicate agent name '" + a.name + "' (also agents[" + std::to_string(it->second) + "])");
  r.seen[a.name] = idx;

  read_dynamics(af, defaults, *out.registry, a);
  const int n = a.dynamics->state_dim(), m = a.dynamics->input_dim();
  const std::string sn = "the dynamics '" + a.dynamics_type + "' has " + std::to_string(n) + " states";
  const std::string sm = "the dynamics '" + a.dynamics_type + "' has " + std::to_string(m) + " inputs";

  // x0 as a point, or as the initial set {center, radius} the problem states (x0_radius: the
  // same half-widths beside a point, also in defaults).
  const Field x0_given = af.required("x0");
  if (x0_given.is_map()) x0_given.allow_only({"center", "radius"});
  const Field x0f = x0_given.is_map() ? x0_given.required("center") : x0_given;
  a.x0 = x0f.vector(n, sn);
  const Field radius_own = x0_given.is_map() ? x0_given.child("radius") : Field(YAML::Node(), x0_given.file(), x0_given.path() + ".radius");
  const Field radius_beside = agent_field(af, defaults, "x0_radius");
  if (radius_own.present() && af.child("x0_radius").present())
    af.child("x0_radius").fail("the initial set's radius is given twice: in x0 {center, radius} and as x0_radius; keep one");
  const Field& radiusf = radius_own.present() ? radius_own : radius_beside;
  if (radiusf.present()) a.x0_radius = radiusf.non_negative_vector(n, sn);
  // `any`: in a goal at any coordinate (the state bounds), in bounds at a periodic one (free turns).
  const std::vector<bool> periodic = a.dynamics->periodic();
  Field goalf = agent_required(af, defaults, "goal");
  a.goal = read_box_any(goalf, n, sn, std::vector<bool>(static_cast<std::size_t>(n), true), "");
  const Field boundsf = agent_required(af, defaults, "state_bounds");
  a.state_bounds = read_box_any(boundsf, n, sn, periodic, bounds_any_rule(*a.dynamics));
  read_agent_workspace(af, defaults, r.spatial, pb, a);
  read_body(af, defaults, boundsf, pb, a);
  lift_periodic(a);
  const Field bodiesf = agent_field(af, defaults, "bodies");
  std::vector<PendingBody> further = bodiesf.present() ? read_further_bodies(bodiesf, pb, a) : std::vector<PendingBody>{};
  for (const PendingBody& b : further)
    if (!b.workspace.linear() && pb.delta_bounds > 0.0)
      bodiesf.fail("delta's bounds keep a body clear of the state bounds of the states its point reads, but body '" + b.name +
                   "' of " + a.name + " is the footprint '" + b.workspace.footprint_name +
                   "', a function of its state with no bounds of its own; give delta's bounds 0 and this agent's state "
                   "bounds with the clearance it needs");
  a.input_bounds = read_box(agent_required(af, defaults, "input_bounds"), m, sm);
  read_disturbance(agent_required(af, defaults, "disturbance"), a, sn);
  // eps and the trackers' fields: numbers, or `auto` (auto_tube.hpp; an absent eps is auto, and
  // so are then absent fields).
  const AutoTube at = read_tube(af, defaults, pb.tau, a, sn, sm, r.tracker_fields, r.tracker_instances);
  out.auto_tube.push_back(at);
  check_periodic_eps(a, agent_field(af, defaults, "eps").present() ? agent_field(af, defaults, "eps") : af);
  validate_agent(a, x0f, radiusf.present() ? radiusf : x0f, goalf, pb.delta_bounds + a.radius);
  check_field_finite(a, agent_field(af, defaults, "dynamics"));
  read_mission(af, pb, a, r);
  // The agent's own tracker, else the default's, else the top level's (Fields are never
  // assigned: a YAML::Node assignment would write into the document).
  const Field tf = agent_field(af, defaults, "tracker");
  const TrackerRequest req = tf.present() ? read_tracker_request(tf, *out.registry) : r.top_tracker;
  out.trackers.push_back(resolve_tracker(a, req, r.tracker_instances, *out.registry, pb, out.memory_budget, af, defaults));
  r.x0_fields.push_back(x0f);
  r.agent_fields.push_back(af);
  r.tracker_requests.push_back(req);
  pb.agents.push_back(std::move(a));
  // Each further body reads the agent as loaded (its tube, bounds, dynamics), with its own map.
  for (PendingBody& b : further) {
    ExtraBody e;
    e.agent = static_cast<int>(pb.agents.size()) - 1;
    e.body = b.name;
    e.spec = pb.agents.back();
    e.spec.name = pb.agents.back().name + "'s " + b.name;
    e.spec.workspace = std::move(b.workspace);
    e.spec.radius = b.radius;
    e.spec.stages.clear();
    pb.extra_bodies.push_back(std::move(e));
  }
}

// The planners' memory against the budget (the main one's and a warm start's, which runs on the
// whole problem first: the larger): the horizon is blamed when a horizon of 1000 steps would
// fit, the agent count otherwise.
void check_planning_memory(const Field& top, LoadedProblem& out, const std::vector<std::shared_ptr<const Planner>>& planners) {
  const Problem& pb = out.problem;
  const double budget = out.memory_budget.bytes;
  const std::string& source = out.memory_budget.source;
  out.plan_memory = {};
  for (const auto& planner : planners) {
    const std::optional<PlannerMemory> own = planner->memory(pb);
    const MemoryEstimate e = own ? MemoryEstimate{own->bytes, own->detail} : planner_memory(pb);
    const std::string whose = own ? planner->name() + "'s own estimate" : "core's estimate for any planner (" + planner->name() + ")";
    if (!(e.bytes <= out.plan_memory.bytes)) {
      out.plan_memory = e;
      out.plan_memory_source = whose;
    }
  }
  const MemoryEstimate& e = out.plan_memory;
  if (!(e.bytes <= budget)) {
    const bool pairs = e.bytes / (pb.horizon + 1.0) * 1001 > budget;
    (pairs ? top.child("agents") : top.child("horizon"))
        .fail("planning would need about " + format_bytes(e.bytes) + " (" + out.plan_memory_source + ": " + e.detail + "), more than the memory budget of " +
              format_bytes(budget) + " (" + source + "); " +
              (pairs ? "use fewer agents" : "shorten the horizon"));
  }
}

// Planner: the default when absent; always checked against the installed plugins so that a
// typo fails here rather than after minutes of work. (Trackers: per agent.) Then
// planner.warm_start: a planner whose plan starts the main one (docs/planning.md, chains).
std::vector<std::shared_ptr<const Planner>> read_planners(const Field& top, const std::string& path, LoadedProblem& out) {
  Problem& pb = out.problem;
  std::vector<std::shared_ptr<const Planner>> planners;
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
    auto made = create_plugin<Planner>(*out.registry, pf);
    planners.push_back(std::move(made.first));
    pb.planner.params = std::move(made.second);
  }
  if (Field p = top.child("planner"); p.present() && !p.is_scalar())
    if (Field w = p.child("warm_start"); w.present()) {
      const PluginField wf = read_plugin_field(w, "name");
      pb.warm_start_planner.name = wf.name;
      auto made = create_plugin<Planner>(*out.registry, wf);
      planners.push_back(std::move(made.first));
      pb.warm_start_planner.params = std::move(made.second);
    }
  return planners;
}

// An auto eps is a first value for the search: beside a kerb or another robot at x0 it starts
// where step 0 is eps-robust, each crowded agent by its own factor (planning::start_eps_factors),
// rather than a plan that fails at once and a search round that narrows it (the others keep
// theirs). A start that leaves no room at all (factor near 0) is left to check's warning.
void narrow_auto_eps_for_starts(Problem& pb, LoadedProblem& out, AgentsRead& r, const Field& defaults) {
  // Judged with the auto tubes 1/0.95 as wide: a start crowded with those is narrowed to 0.95 of
  // what makes it exactly robust, so that none is left with a margin of 0 (a car exactly
  // delta + radius + eps from a kerb, short by 3e-8 between the first two samples).
  if (std::none_of(out.auto_tube.begin(), out.auto_tube.end(), [](const AutoTube& t) { return t.eps; })) return;
  Problem wider = pb;
  for (std::size_t i = 0; i < pb.agents.size(); ++i)
    if (out.auto_tube[i].eps) wider.agents[i].tube.eps /= 0.95;
  const std::vector<double> factor = planning::start_eps_factors(wider);
  for (std::size_t i = 0; i < pb.agents.size(); ++i) {
    if (!out.auto_tube[i].eps || !(factor[i] < 1) || !(factor[i] > 0.05)) continue;
    AgentSpec& a = pb.agents[i];
    const double f = factor[i];
    a.tube.eps *= f;
    out.auto_tube[i].start_cap = "x " + number_text(f, 3) + " where its start is crowded (0.95 of what makes step 0 eps-robust)";
    follow_tube(r.tracker_instances, a, TubeChange::Set);
    out.trackers[i] = resolve_tracker(a, r.tracker_requests[i], r.tracker_instances, *out.registry, pb, out.memory_budget,
                                      r.agent_fields[i], defaults);
  }
}

}  // namespace

LoadedProblem load_problem(const std::string& path, const LoadOptions& options) {
  const YAML::Node root = yaml::load_file(path);
  Field top(root, path, "");
  top.expect_map();
  top.allow_only(kTopKeys);

  LoadedProblem out;
  out.memory_budget = options.memory_budget;
  Problem& pb = out.problem;
  pb.source = path;
  pb.name = top.child("name").present() ? top.child("name").text() : name_from_stem(fs::path(path).stem().string());
  if (top.child("name").present())
    if (const std::string why = name_defect(pb.name); !why.empty()) top.child("name").fail(why);

  // Plugins first: the dynamics decide every dimension checked below.
  read_plugin_paths(top, path, out);
  read_timing_and_norms(top, out);

  TrackerInstances tracker_instances(out.registry);
  const std::vector<AgentFieldSpec> tracker_fields = installed_agent_fields(tracker_instances);
  const std::vector<std::string> keys = agent_keys(tracker_fields);
  const Field defaults = top.child("defaults");
  if (defaults.present()) {
    defaults.expect_map();
    std::vector<std::string> allowed(keys.begin() + 1, keys.end());
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
  const Field regions = top.child("regions");
  check_regions(regions);
  // The top-level tracker (default of every agent without its own): a name, a block, or auto.
  const TrackerRequest top_tracker = read_tracker_request(top.child("tracker"), *out.registry);
  pb.tracker = top_tracker.automatic ? PluginChoice{kAutoTracker, {}} : top_tracker.choice;
  AgentsRead r{defaults, regions, spatial, top_tracker, tracker_instances, tracker_fields, keys, {}, {}, {}, {}, {}, {}, {}};
  for (std::size_t idx = 0; idx < agent_fields.size(); ++idx) read_agent(agent_fields[idx], idx, out, r);

  if (has_obstacles) {
    const auto obs = top.child("obstacles").items();
    for (std::size_t i = 0; i < obs.size(); ++i) pb.obstacles.push_back(read_obstacle(obs[i], i, pb.workspace_dim));
  }
  for (std::size_t i = 0; i < r.ltl_fields.size(); ++i) check_ltl_avoid(r.ltl_fields[i], r.ltl_avoid[i], pb.obstacles);
  if (Field f = top.child("formation"); f.present()) {
    read_formation(f, pb);
    // An auto eps is a first value for the search; inside a formation it starts where the pair's
    // tolerance leaves a robust plan (the trackers judged again on the narrower tube).
    for (std::size_t i = 0; i < pb.agents.size(); ++i) {
      AgentSpec& a = pb.agents[i];
      if (!out.auto_tube[i].eps || !cap_auto_eps_for_formation(a, formation_tolerance(pb, static_cast<int>(i)))) continue;
      follow_tube(r.tracker_instances, a, TubeChange::Set);
      out.trackers[i] = resolve_tracker(a, r.tracker_requests[i], r.tracker_instances, *out.registry, pb, out.memory_budget,
                                        r.agent_fields[i], defaults);
    }
  }
  check_teams(pb, r.stage_fields);
  read_stage_obstacles(pb, r.stage_fields, top.child("obstacles"));
  branch_by_route(pb);  // an angle's goal on the branch the way there winds to (a patrol's full turn)
  check_start_geometry(pb, r.x0_fields);
  narrow_auto_eps_for_starts(pb, out, r, defaults);
  check_planning_memory(top, out, read_planners(top, path, out));
  if (Field f = top.child("collision"); f.present()) read_collision(f, out);
  return out;
}

}  // namespace marsyn
