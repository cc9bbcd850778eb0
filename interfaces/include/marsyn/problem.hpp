#pragma once
// The problem value types every stage reads (architecture: plain values flowing one way).
// Units: states and inputs in the model's units; time in seconds (tau) or steps (k, horizon).
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "marsyn/box.hpp"
#include "marsyn/constraint.hpp"
#include "marsyn/dynamics.hpp"
#include "marsyn/params.hpp"

namespace marsyn {

// How an agent's state maps to a point in the shared workspace (obstacles, collisions,
// formation): the plane (2 coordinates) or space (3, `position: [x, y, z]`; linear maps only).
struct Workspace {
  // Linear map: p[c] = x[index[c]] + offset[c], or offset[c] alone when index[c] < 0; one entry
  // per workspace coordinate (2 or 3).
  std::vector<int> index{0, 1};
  std::vector<double> offset{0.0, 0.0};
  // A model-provided nonlinear footprint (e.g. the crane's pendulum tip); -1 for the linear map.
  int footprint = -1;
  std::string footprint_name;

  bool linear() const { return footprint < 0; }
  // 2 (the plane) or 3; footprints are planar.
  int dim() const { return linear() ? static_cast<int>(index.size()) : 2; }
};

// The largest workspace dimension: arrays of workspace coordinates are sized by it.
inline constexpr int kMaxWorkspaceDim = 3;

// p = workspace point of state x (ws.dim() coordinates). Works for double, DualD and Interval.
template <class S>
void workspace_point(const Dynamics& dyn, const Workspace& ws, const S* x, S* p) {
  if (!ws.linear()) {
    dyn.footprint(ws.footprint, x, p);
    return;
  }
  for (int c = 0; c < ws.dim(); ++c)
    p[c] = ws.index[c] >= 0 ? x[ws.index[c]] + ws.offset[c] : S(ws.offset[c]);
}

// The point with 3 coordinates: z = 0 in a planar workspace (where no obstacle bounds z), so
// that one formula judges both.
template <class S>
void workspace_point3(const Dynamics& dyn, const Workspace& ws, const S* x, S* p) {
  p[2] = S(0.0);
  workspace_point(dyn, ws, x, p);
}

struct PluginChoice {
  std::string name;
  Params params;
};

// One agent's tube (paper Sec. 3), as the problem file gives it and every stage passes it on:
// the disturbance bound and the tube's half-width.
// A term of a disturbance bound that grows with the magnitude of one state or input coordinate
// (wheel slip with speed): it adds gain[i] |s| to W_i, s = x[index] or u[index].
struct DisturbanceGrowth {
  bool input = false;    // s is an input (u[index]), else a state (x[index])
  int index = 0;
  std::string name;      // the coordinate's name, for messages
  Eigen::VectorXd gain;  // n numbers >= 0, one per state coordinate of W
};

struct TubeParams {
  // Disturbance bound: w in [-w, w] componentwise, for every state in X and input in U. When W
  // grows with the state (w_growth below) this is its largest value there, so that a reader of
  // w alone (a tracker without TrackerCapabilities::state_dependent_disturbance) stays sound.
  Eigen::VectorXd w;
  Eigen::VectorXd eps;  // tube half-width per state coordinate (robustness margin)
  // W(x, u) = w_base + sum_t gain_t |s_t| (marsyn/disturbance.hpp); empty w_growth: W = w.
  Eigen::VectorXd w_base;
  std::vector<DisturbanceGrowth> w_growth;

  bool state_dependent() const { return !w_growth.empty(); }
};

// An agent-level field that belongs to a tracker, not to the problem: abcd's grid (eta_x,
// eta_u), written at the agent level in the paper's notation (docs/problem-format.md). The
// tracker declares it (Tracker::agent_fields); the loader reads it as numbers or `auto`; core
// carries it and reports it by name without interpreting it; its owner reads it, derives it when
// automatic and keeps it in step with the tube (Tracker::follow_tube).
struct AgentField {
  std::string name;
  Eigen::VectorXd value;   // empty: not given
  bool automatic = false;  // `auto` (or absent under an auto eps): its owner derives it from the tube
};

// An agent's tracker-owned fields, in the order the trackers declare them.
struct AgentFields {
  std::vector<AgentField> items;

  const AgentField* find(std::string_view name) const {
    for (const auto& f : items)
      if (f.name == name) return &f;
    return nullptr;
  }
  AgentField* find(std::string_view name) {
    for (auto& f : items)
      if (f.name == name) return &f;
    return nullptr;
  }
  // The value of `name`; empty when absent or not given.
  Eigen::VectorXd value(std::string_view name) const {
    const AgentField* f = find(name);
    return f ? f->value : Eigen::VectorXd();
  }
  // Sets the value of `name` (appended, not automatic, the first time).
  void set(std::string_view name, Eigen::VectorXd v) {
    if (AgentField* f = find(name)) f->value = std::move(v);
    else items.push_back({std::string(name), std::move(v), false});
  }
};

// One stage of an agent's mission (docs/tasks.md): a region the agent visits, in the order
// listed, before its goal (the goal stays the last stage). The visit knot is chosen by the
// schedule (core planning/mission) inside the window [not_before, by]; the agent stays inside
// at the knots visit..visit+dwell (and between them under the continuous guarantee).
struct MissionStage {
  std::string name;
  Box box;                                // a box in the agent's state coordinates, or
  std::vector<Eigen::Vector2d> polygon;   // a convex polygon (counter-clockwise) in the workspace plane
  int not_before = 1;                     // earliest visit knot
  int by = -1;                            // latest visit knot; -1: none
  int dwell = 0;                          // further knots spent inside after the visit
  std::string team;                       // stages sharing a team label are visited at one knot (rendezvous)
  // Obstacles (indices into Problem::obstacles, each with `staged` set) the agent avoids only on
  // the way to this stage (from the previous stage's last dwell knot, or step 0, to this one's),
  // and from this stage's last dwell knot to the horizon (a door that closes behind it).
  std::vector<int> avoid, avoid_after;

  bool is_polygon() const { return !polygon.empty(); }
};

struct AgentSpec {
  std::string name;
  std::string dynamics_type;
  std::shared_ptr<const Dynamics> dynamics;
  Eigen::VectorXd x0;
  // The initial set the problem states (`x0: {center, radius}` or `x0_radius`): the robot starts
  // anywhere in x0 +- x0_radius, and every controller must accept that whole box at step 0.
  // Empty: the start is x0 exactly (as zeros).
  Eigen::VectorXd x0_radius;
  Box goal;         // Goal^i, in state coordinates
  Box state_bounds;  // X^i
  Box input_bounds;  // U^i
  TubeParams tube;  // w, eps: what the agent's tracker is asked to keep
  AgentFields fields;  // the trackers' own agent-level fields (abcd's grid), core never reads them
  Workspace workspace;
  // The body's half-width around its workspace point (a square in the inf-norm, a disc in the
  // 2-norm): added to every clearance the agent keeps, pairwise between two agents (`radius`).
  double radius = 0.0;
  std::string body;  // the first body's name when the agent lists `bodies` ("tractor"); else empty
  // The agent's tracker (name and parameters); the name is never "auto" once the problem is
  // loaded: the loader resolves `tracker: auto` per agent from each tracker's assessment.
  PluginChoice tracker;
  std::vector<MissionStage> stages;  // visited in order before the goal; empty: the goal alone

  int n() const { return static_cast<int>(x0.size()); }
  double x0_half(int i) const { return i < x0_radius.size() ? x0_radius[i] : 0.0; }
  int m() const { return static_cast<int>(input_bounds.lo.size()); }
};

enum class Norm { Inf, Two };

struct Obstacle {
  std::string name;
  // Convex polygon, counter-clockwise; an axis-aligned box is stored as its 4 corners.
  std::vector<Eigen::Vector2d> vertices;
  bool is_box = false;
  // The vertical extent of the prism polygon x [z_lo, z_hi] in a 3-D workspace; unbounded in the
  // plane (and for full-height obstacles), where the obstacle is the polygon alone.
  double z_lo = -std::numeric_limits<double>::infinity();
  double z_hi = std::numeric_limits<double>::infinity();
  bool z_bounded() const { return z_lo > -std::numeric_limits<double>::infinity() || z_hi < std::numeric_limits<double>::infinity(); }
  // `scope: stages`: binds an agent only where one of its mission stages names it
  // (MissionStage::avoid, avoid_after); otherwise every agent at every time.
  bool staged = false;
};

// A further body of an agent (`bodies:`, a tractor's cart): a point of the agent's own state with
// a radius. `spec` is the owner's AgentSpec with this body's workspace map, radius and name
// ("rig1's cart"), so that everything written for an agent's point reads it unchanged; its state
// is the owner's (agent's slice of the product state).
struct ExtraBody {
  int agent = 0;     // the owner, an index into Problem::agents
  std::string body;  // the body's own name ("cart")
  AgentSpec spec;
};

struct FormationPair {
  int i = 0, j = 0;     // agent indices
  double lambda = 0.0;  // desired Euclidean distance between the workspace points
  double mu = 0.0;      // tolerance: lambda - mu <= d_ij <= lambda + mu
};

// Builds a distance provider (e.g. the "fcl" plugin) over planar obstacles: convex polygons,
// counter-clockwise, numbered in the order given. The problem loader makes one from the config's
// `collision` choice; when empty, planners use core's exact polygon geometry.
using DistanceModelFactory =
    std::function<std::shared_ptr<const DistanceModel>(const std::vector<std::vector<Eigen::Vector2d>>& polygons)>;

// Which times the safety part of the specification (state bounds, obstacles, collisions,
// formation) is guaranteed for: every t in [0, T tau] (default), or only the sampling instants
// t = k tau (the paper's discrete-time semantics, kept for comparison with its Table 2).
enum class Guarantee { Continuous, Sampled };

inline const char* to_string(Guarantee g) { return g == Guarantee::Continuous ? "continuous" : "sampled"; }

struct Problem;

// Where each agent's coordinates sit in the product state and input: the agents side by side in
// the order of the problem file. The one definition that planners, projection, the checks, the
// global baseline and the reports read (agent i's state is x.segment(state[i], n_i)).
struct ProductLayout {
  std::vector<int> state{0}, input{0};  // per agent its first coordinate, then the total
  explicit ProductLayout(const std::vector<AgentSpec>& agents) {
    for (const auto& a : agents) {
      state.push_back(state.back() + a.n());
      input.push_back(input.back() + a.m());
    }
  }
  explicit ProductLayout(const Problem& problem);  // of problem.agents
  int state_dim() const { return state.back(); }
  int input_dim() const { return input.back(); }
};

struct Problem {
  std::string name;
  std::string source;  // the file it was loaded from
  std::vector<AgentSpec> agents;
  std::vector<Obstacle> obstacles;
  int workspace_dim = 2;   // every agent's workspace dimension: 2 (plane) or 3 (space)
  double delta = 0.0;      // safety distance between agents (and to obstacles unless delta_obstacles is set)
  // Clearance to obstacles when it differs from the agents' (`delta: {agents: a, obstacles: o}`):
  // a robot keeps one body from a wall, two bodies from another robot. Negative: `delta`.
  double delta_obstacles = -1.0;
  double obstacle_delta() const { return delta_obstacles >= 0.0 ? delta_obstacles : delta; }
  // Clearance of a body from the state bounds in its workspace coordinates (`delta: {bounds: b}`);
  // the loader has already pulled each agent's state bounds in by it plus the agent's radius.
  double delta_bounds = 0.0;
  // What each requirement keeps, with the bodies' radii: two agents keep delta plus both radii,
  // an agent keeps the obstacles' delta plus its own.
  // Indices are body slots (below): the agents' first bodies 0..N-1, then the further ones.
  double pair_clearance(int a, int b) const { return delta + body_spec(a).radius + body_spec(b).radius; }
  double obstacle_clearance(int a) const { return obstacle_delta() + body_spec(a).radius; }
  double largest_radius() const {
    double r = 0.0;
    for (const auto& a : agents) r = r > a.radius ? r : a.radius;
    for (const auto& e : extra_bodies) r = r > e.spec.radius ? r : e.spec.radius;
    return r;
  }
  // Bounds on every pair's and every agent's clearance, for screens that skip far requirements.
  // (Summed in pair_clearance's order: rounding is monotone, so no pair's value exceeds it.)
  double largest_pair_clearance() const { return delta + largest_radius() + largest_radius(); }
  double largest_obstacle_clearance() const { return obstacle_delta() + largest_radius(); }
  Norm delta_norm = Norm::Inf;
  bool pairwise_collision = true;
  Guarantee guarantee = Guarantee::Continuous;
  std::vector<FormationPair> formation;
  // The agents' further bodies, in agent order. Body slot s < N is agent s's first body (its
  // `workspace` and `radius`), slot N + e is extra_bodies[e]; obstacles bind every slot, pairs
  // every two slots of different agents.
  std::vector<ExtraBody> extra_bodies;
  int body_count() const { return static_cast<int>(agents.size() + extra_bodies.size()); }
  int body_agent(int s) const {
    const int n = static_cast<int>(agents.size());
    return s < n ? s : extra_bodies[static_cast<std::size_t>(s - n)].agent;
  }
  const AgentSpec& body_spec(int s) const {
    const int n = static_cast<int>(agents.size());
    return s < n ? agents[static_cast<std::size_t>(s)] : extra_bodies[static_cast<std::size_t>(s - n)].spec;
  }
  double tau = 0.1;        // sampling time [s]
  int horizon = 0;         // T [steps]
  int rk4_substeps = 4;    // substeps of the sampled map f_tau used by planners and simulation
  PluginChoice planner;
  PluginChoice warm_start_planner;  // optional: its plan starts `planner` (name empty: none)
  PluginChoice tracker;  // the top-level request: a tracker or "auto"; each agent's own is AgentSpec::tracker
  PluginChoice collision;              // name empty: core's exact geometry
  DistanceModelFactory distance_model;  // set with a collision plugin
  std::vector<std::string> plugin_paths;

  int product_state_dim() const { return ProductLayout(agents).state_dim(); }
  int product_input_dim() const { return ProductLayout(agents).input_dim(); }
};

inline ProductLayout::ProductLayout(const Problem& problem) : ProductLayout(problem.agents) {}

// A plan for the product system: x[0..T] (product states), u[0..T-1] (product inputs).
struct GlobalPlan {
  double tau = 0.1;
  std::vector<Eigen::VectorXd> x;
  std::vector<Eigen::VectorXd> u;
  int horizon() const { return static_cast<int>(u.size()); }
};

// One agent's share of a plan (paper Alg. 1 step 2): its nominal trajectory rho^i.
struct NominalTrajectory {
  std::string agent;
  std::vector<Eigen::VectorXd> x;  // x_0..x_T
  std::vector<Eigen::VectorXd> u;  // u_0..u_{T-1}
};

}  // namespace marsyn
