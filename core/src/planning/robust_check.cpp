#include "marsyn/core/planning/robust_check.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <thread>

#include "marsyn/core/parallel_tasks.hpp"
#include "marsyn/core/planning/box_margins.hpp"
#include "marsyn/core/planning/constraints.hpp"
#include "marsyn/core/planning/flow_enclosure.hpp"
#include "marsyn/core/planning/geometry.hpp"
#include "marsyn/core/planning/lowest_first.hpp"
#include "marsyn/core/planning/margins.hpp"
#include "marsyn/core/planning/mission.hpp"
#include "marsyn/core/planning/spec_margins.hpp"
#include "marsyn/fast_interval.hpp"
#include "marsyn/interval.hpp"
#include "marsyn/sampled_map.hpp"
#include "marsyn/number_text.hpp"

namespace marsyn::planning {

std::vector<Eigen::VectorXd> rollout(const Problem& problem, const std::vector<Eigen::VectorXd>& inputs) {
  const ProductLayout at(problem);
  const auto &xo = at.state, &uo = at.input;
  std::vector<Eigen::VectorXd> x(inputs.size() + 1, Eigen::VectorXd(xo.back()));
  for (size_t i = 0; i < problem.agents.size(); ++i) x[0].segment(xo[i], problem.agents[i].n()) = problem.agents[i].x0;
  for (size_t k = 0; k < inputs.size(); ++k)
    for (size_t i = 0; i < problem.agents.size(); ++i)
      rk4_step<double>(*problem.agents[i].dynamics, x[k].data() + xo[i], inputs[k].data() + uo[i], nullptr,
                       problem.tau, problem.rk4_substeps, x[k + 1].data() + xo[i]);
  return x;
}

namespace {

// The agents a requirement binds (its body slots' owners; a formation's are agents already).
std::array<int, 2> agents_of(const Problem& problem, const Requirement& q) {
  switch (q.kind) {
    case Requirement::Obstacle: return {problem.body_agent(q.a), -1};
    case Requirement::Collision: return {problem.body_agent(q.a), problem.body_agent(q.b)};
    case Requirement::Formation: break;
  }
  return {q.a, q.b};
}

// Each agent's body slots: its first body, then its further ones.
std::vector<std::vector<int>> bodies_by_agent(const Problem& problem) {
  std::vector<std::vector<int>> out(problem.agents.size());
  for (int s = 0; s < problem.body_count(); ++s) out[static_cast<size_t>(problem.body_agent(s))].push_back(s);
  return out;
}

class Tally {
 public:
  // Names are built only for new minima: the 50-agent check visits ~10^5 requirements per plan.
  void record(double margin, int k, const std::function<std::string()>& name, std::array<int, 2> who = {-1, -1}) {
    if (!(margin >= min_)) {  // also catches NaN
      min_ = std::isnan(margin) ? -std::numeric_limits<double>::infinity() : margin;
      step_ = k;
      name_ = name();
      who_ = who;
    }
  }
  double min_ = std::numeric_limits<double>::infinity();
  int step_ = -1;
  std::string name_;
  std::array<int, 2> who_{-1, -1};
};

// A tally that also keeps every violated requirement by name (the continuous-time check's
// targets for more clearance).
class NamedTally : public Tally {
 public:
  void record(double margin, int k, const std::function<std::string()>& name, double motion = 0.0,
              std::array<int, 2> who = {-1, -1}, bool collision = false) {
    Tally::record(margin, k, name, who);
    if (!(margin >= 0)) {
      const std::string n = name();
      auto [it, fresh] = negative.try_emplace(n, BetweenShortfall{margin, motion, collision});
      if (!fresh) {
        it->second.margin = std::min(it->second.margin, margin);
        it->second.motion = std::max(it->second.motion, motion);
      }
    }
  }
  // Takes another tally's minimum and shortfalls (a period checked on its own).
  void merge(const NamedTally& o) {
    if (!(o.min_ >= min_)) {
      min_ = o.min_;
      step_ = o.step_;
      name_ = o.name_;
      who_ = o.who_;
    }
    for (const auto& [n, b] : o.negative) {
      auto [it, fresh] = negative.try_emplace(n, b);
      if (!fresh) {
        it->second.margin = std::min(it->second.margin, b.margin);
        it->second.motion = std::max(it->second.motion, b.motion);
      }
    }
  }
  std::map<std::string, BetweenShortfall> negative;
};

// The boxes' heap vectors, kept from one period to the next (they were a tenth of the check).
struct PeriodScratch {
  std::vector<std::vector<Box>> ws;
  std::vector<Box> flow;
  std::vector<Box> hull;       // per agent, its workspace boxes over the whole period
  std::vector<double> floor;   // per requirement (visiting order), its margin on those hulls
  std::vector<std::vector<int>> bodies;  // per agent its body slots (bodies_by_agent), made once
};

// out = the box f grown by eps, outward rounding (out sized like f). Directed rounding in
// round-to-nearest, not Boost.Interval on point intervals: GCC computes both ends of one such
// expression once, in the mode it set first (docs/soundness.md, section 7).
void grow_by_eps(const Box& f, const Eigen::VectorXd& eps, Box& out) {
  const RoundToNearestScope nearest;
  for (int c = 0; c < f.dim(); ++c) {
    out.lo[c] = fast_detail::sub_down(f.lo[c], eps[c]);
    out.hi[c] = fast_detail::add_up(f.hi[c], eps[c]);
  }
}

// A requirement's margin over a part is at least its margin over the period's hull boxes (the
// box margins are distances between boxes, or tight lower bounds of them, and shrink as the
// boxes grow): floor_decides (lowest_first.hpp) tells where a part cannot change the tally.

// One enclosure of each agent's flow over a whole period (flow_boxes with one part), kept for
// the period's parts: a part's box is its own enclosure intersected with it (both enclose the
// flow over the part), so every part lies in it and its margins bound the parts' from below.
struct PeriodBoxes {
  std::vector<Box> box;
  std::vector<char> have;  // 0: no one-part enclosure (the parts are then taken as they come)
};

// What a user can change when the flow has no enclosure over a period.
constexpr const char* kNoEnclosureHint =
    " over one period (its a priori enclosure did not close: a shorter tau or smaller inputs let it)";

// The eps-box around the exact flow between samples k and k+1 (every agent, `parts` parts),
// against bounds, obstacles, the other agents in the same part of the period, and formation.
// Returns false when a part has no enclosure (recorded as -inf).
bool check_period(const Problem& problem, const ProductLayout& at, const std::vector<Eigen::VectorXd>& x,
                  const std::vector<Eigen::VectorXd>& u, int k, int parts, const ObstacleWindows& windows,
                  const PeriodBoxes& whole, bool floors, PeriodScratch& scratch, NamedTally& t) {
  const auto &xo = at.state, &uo = at.input;
  const int N = static_cast<int>(problem.agents.size()), B = problem.body_count();
  const int P = parts;
  // ws[s][b]: body b's workspace box over part s of the period.
  const int D = problem.workspace_dim;
  auto& ws = scratch.ws;
  if (static_cast<int>(ws.size()) < P) ws.resize(static_cast<size_t>(P));
  for (int s = 0; s < P; ++s)
    if (ws[s].size() != static_cast<size_t>(B)) ws[s].assign(static_cast<size_t>(B), Box{Eigen::VectorXd(D), Eigen::VectorXd(D)});
  if (scratch.bodies.size() != static_cast<size_t>(N)) scratch.bodies = bodies_by_agent(problem);
  const std::vector<std::vector<int>>& bodies = scratch.bodies;
  auto& flow = scratch.flow;
  std::vector<Interval> xb, pb(kMaxWorkspaceDim);
  const bool inf = problem.delta_norm == Norm::Inf;
  // Knot-to-knot motion of the workspace points: an agent's own (obstacles) and, for a pair, of
  // their difference (collisions, formation), in the problem's norm.
  std::vector<Point> step(static_cast<size_t>(B));
  auto size = [&](const Point& d) { return inf ? d.lpNorm<Eigen::Infinity>() : distance2(d); };
  {
    std::vector<Point> p0, p1;
    body_points(problem, xo, x[k].data(), p0);
    body_points(problem, xo, x[k + 1].data(), p1);
    for (int b = 0; b < B; ++b) step[static_cast<size_t>(b)] = p1[static_cast<size_t>(b)] - p0[static_cast<size_t>(b)];
  }
  for (int i = 0; i < N; ++i) {
    const auto& a = problem.agents[i];
    const Eigen::VectorXd xi = x[k].segment(xo[i], a.n()), ui = u[k].segment(uo[i], a.m());
    // The exact disturbance-free flow from the nominal state under the nominal input (the
    // continuous nominal), each part's box grown by eps: the eps-robust spec between the
    // samples. The tube's own excursion within a period is what the certifier measures on the
    // trackers' enclosures; where it falls short, the outer search adds clearance to exactly
    // those constraints (AssemblyOptions::extra).
    const Box point{xi, xi};
    const Box* period = whole.have[i] ? &whole.box[i] : nullptr;
    if (!flow_boxes(*a.dynamics, point, ui, Eigen::VectorXd::Zero(a.n()), problem.tau, P, flow)) {
      if (!period) {
        t.record(-std::numeric_limits<double>::infinity(), k, [&] { return "no enclosure of the flow of " + a.name + kNoEnclosureHint; });
        return false;
      }
      flow.assign(static_cast<size_t>(P), *period);
    } else if (period) {
      for (auto& f : flow) {
        f.lo = f.lo.cwiseMax(period->lo);
        f.hi = f.hi.cwiseMin(period->hi);
      }
    }
    Box grown{Eigen::VectorXd(a.n()), Eigen::VectorXd(a.n())};
    for (int s = 0; s < P; ++s) {
      grow_by_eps(flow[s], a.tube.eps, grown);
      for (int c = 0; c < a.n(); ++c)
        t.record(box_inside_margin(grown, a.state_bounds, c), k, [&] { return state_bound_name(a, c); },
                 std::abs(x[k + 1][xo[i] + c] - x[k][xo[i] + c]));
      for (int b : bodies[static_cast<size_t>(i)]) workspace_box(problem.body_spec(b), D, grown, xb, pb, ws[s][b]);
    }
  }
  auto motion = [&](const Requirement& q) {
    if (q.kind == Requirement::Obstacle) return size(step[q.a]);
    const Point d = step[q.a] - step[q.b];
    return q.kind == Requirement::Collision ? size(d) : distance2(d);
  };
  // Each requirement once on the hull of its agents' boxes over the period, then part by part
  // where that floor leaves the outcome open (same tally as every part of every requirement).
  auto& hull = scratch.hull;
  if (floors) hull.assign(ws[0].begin(), ws[0].begin() + B);
  for (int s = 1; floors && s < P; ++s)
    for (int i = 0; i < B; ++i) {
      hull[i].lo = hull[i].lo.cwiseMin(ws[s][i].lo);
      hull[i].hi = hull[i].hi.cwiseMax(ws[s][i].hi);
    }
  auto& floor = scratch.floor;
  floor.clear();
  if (floors)
    for_each_requirement(problem, windows, Moment{k, true},
                         [&](const Requirement& q) { floor.push_back(box_requirement_margin(problem, q, hull)); });
  for (int s = 0; s < P; ++s) {
    std::size_t r = 0;
    for_each_requirement(problem, windows, Moment{k, true}, [&](const Requirement& q) {
      if (floors && floor_decides(floor[r++], t.min_)) return;
      t.record(box_requirement_margin(problem, q, ws[s]), k, [&] { return q.name(problem); }, motion(q),
               agents_of(problem, q), q.kind == Requirement::Collision);
    });
  }
  return true;
}

// The one-part enclosures of period k (whole) and a lower bound of every margin check_period
// can record in that period: its margins on those boxes (the parts lie inside them, and the box
// margins only shrink as boxes grow). -inf where an agent has no one-part enclosure.
double period_floor(const Problem& problem, const ProductLayout& at, const std::vector<Eigen::VectorXd>& x,
                    const std::vector<Eigen::VectorXd>& u, int k, const ObstacleWindows& windows,
                    PeriodScratch& scratch, PeriodBoxes& whole) {
  const int N = static_cast<int>(problem.agents.size()), D = problem.workspace_dim;
  whole.box.resize(static_cast<size_t>(N));
  whole.have.assign(static_cast<size_t>(N), 0);
  auto& hull = scratch.hull;
  hull.assign(static_cast<size_t>(problem.body_count()), Box{Eigen::VectorXd(D), Eigen::VectorXd(D)});
  if (scratch.bodies.size() != static_cast<size_t>(N)) scratch.bodies = bodies_by_agent(problem);
  const std::vector<std::vector<int>>& bodies = scratch.bodies;
  std::vector<Interval> xb, pb(kMaxWorkspaceDim);
  double low = std::numeric_limits<double>::infinity();
  auto take = [&](double m) {
    if (!(m >= low)) low = std::isnan(m) ? -std::numeric_limits<double>::infinity() : m;
  };
  for (int i = 0; i < N; ++i) {
    const auto& a = problem.agents[i];
    const Eigen::VectorXd xi = x[k].segment(at.state[i], a.n()), ui = u[k].segment(at.input[i], a.m());
    if (!flow_boxes(*a.dynamics, Box{xi, xi}, ui, Eigen::VectorXd::Zero(a.n()), problem.tau, 1, scratch.flow)) {
      take(-std::numeric_limits<double>::infinity());
      continue;
    }
    whole.box[i] = scratch.flow[0];
    whole.have[i] = 1;
    Box grown{Eigen::VectorXd(a.n()), Eigen::VectorXd(a.n())};
    grow_by_eps(whole.box[i], a.tube.eps, grown);
    for (int c = 0; c < a.n(); ++c) take(box_inside_margin(grown, a.state_bounds, c));
    for (int b : bodies[static_cast<size_t>(i)]) workspace_box(problem.body_spec(b), D, grown, xb, pb, hull[b]);
  }
  if (low == -std::numeric_limits<double>::infinity()) return low;
  for_each_requirement(problem, windows, Moment{k, true},
                       [&](const Requirement& q) { take(box_requirement_margin(problem, q, hull)); });
  return low;
}

// Every period with kFlowParts parts; a period that falls short is checked again with finer
// parts (kFlowRefinement times as many, up to kFlowMaxParts): each part's box still encloses the
// flow over that part, so the finer verdict is as sound and less pessimistic by the motion over
// a part that a coarse box adds.
//
// With floors, the parts are computed only where they can matter: every period first gets its
// one-part boxes and their floor (period_floor, about a sixth of the parts' cost); the periods
// are then checked part by part from the lowest floor up, and a period whose floor is above the
// smallest margin found so far (and above zero) by more than rounding is skipped: none of its
// margins could be a new minimum or a shortfall. Same result bit for bit as checking every period.
void check_between_samples(const Problem& problem, const std::vector<Eigen::VectorXd>& x,
                           const std::vector<Eigen::VectorXd>& u, const ObstacleWindows& windows, bool floors,
                           NamedTally& t) {
  const int T = static_cast<int>(u.size());
  const ProductLayout at(problem);
  // The periods are independent: checked on every core (on one, the check was a fourteenth of
  // multi_drone's plan stage) in contiguous runs, each run with its own scratch; the tallies are
  // merged in period order, as one pass would, up to the first period without an enclosure. Same
  // result bit for bit on any number of threads.
  std::vector<NamedTally> periods(static_cast<size_t>(T));
  std::vector<char> enclosed(static_cast<size_t>(T), 1), checked(static_cast<size_t>(T), 0);
  std::vector<PeriodBoxes> whole(static_cast<size_t>(T));
  std::vector<double> low(static_cast<size_t>(T));
  const int threads = std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, 8);
  auto in_runs = [&](int n, auto&& each) {
    const int runs = std::min(n, 4 * threads);
    parallel_tasks(runs, threads, [&](int r) {
      PeriodScratch scratch;
      const int begin = static_cast<int>(static_cast<long>(n) * r / runs);
      const int end = static_cast<int>(static_cast<long>(n) * (r + 1) / runs);
      for (int j = begin; j < end; ++j) each(j, scratch);
    });
  };
  auto check = [&](int k, PeriodScratch& scratch) {
    NamedTally& period = periods[static_cast<size_t>(k)];
    int parts = kFlowParts;
    bool ok = check_period(problem, at, x, u, k, parts, windows, whole[k], floors, scratch, period);
    while (ok && !(period.min_ >= 0) && parts * kFlowRefinement <= kFlowMaxParts) {
      parts *= kFlowRefinement;
      period = NamedTally();
      ok = check_period(problem, at, x, u, k, parts, windows, whole[k], floors, scratch, period);
    }
    enclosed[static_cast<size_t>(k)] = ok;
    checked[static_cast<size_t>(k)] = 1;
  };
  in_runs(T, [&](int k, PeriodScratch& s) { low[k] = period_floor(problem, at, x, u, k, windows, s, whole[k]); });
  if (!floors) {
    in_runs(T, check);
  } else {
    // The smallest margin so far bounds the final one from above; so does a minimum already in
    // t (the mission stages').
    std::vector<PeriodScratch> scratch(static_cast<size_t>(threads));
    lowest_first(low, t.min_, threads, [&](int k, int worker) {
      check(k, scratch[static_cast<size_t>(worker)]);
      return periods[static_cast<size_t>(k)].min_;
    });
  }
  for (int k = 0; k < T; ++k) {
    if (checked[static_cast<size_t>(k)]) t.merge(periods[static_cast<size_t>(k)]);
    if (!enclosed[static_cast<size_t>(k)]) return;
  }
}

// The eps-box of state x of agent a (outward rounding) and its workspace box (linear maps; a
// footprint's workspace box is not needed: polygon stages need a linear map).
Box eps_box(const AgentSpec& a, const Eigen::VectorXd& x) {
  Box b{Eigen::VectorXd(a.n()), Eigen::VectorXd(a.n())};
  for (int c = 0; c < a.n(); ++c) {
    const Interval v = Interval(x[c]) + Interval(-a.tube.eps[c], a.tube.eps[c]);
    b.lo[c] = v.lower();
    b.hi[c] = v.upper();
  }
  return b;
}

Box workspace_of(const AgentSpec& a, const Box& state) {
  return a.workspace.linear() ? linear_workspace_box(a.workspace, state)
                              : Box{Eigen::VectorXd::Constant(2, -INFINITY), Eigen::VectorXd::Constant(2, INFINITY)};
}

// Each stage at the plan's knots, and between them while it dwells (continuous guarantee):
// the sampled margins into t, the between-samples ones into b (by the stage's name, so that a
// shortfall there becomes clearance for the stage in the next assembly).
std::vector<StageVisit> check_stages(const Problem& problem, const std::vector<Eigen::VectorXd>& x,
                                     const std::vector<Eigen::VectorXd>& u, const MissionSchedule& sched, Tally& t,
                                     NamedTally* b) {
  const int T = static_cast<int>(u.size());
  const ProductLayout at(problem);
  if (!sched.feasible)
    t.record(-std::numeric_limits<double>::infinity(), T, [&] { return "mission schedule: " + sched.why; });
  std::vector<StageVisit> visits = stage_visits(problem, sched);
  std::vector<Box> flow;
  for (auto& v : visits) {
    const auto& a = problem.agents[v.agent];
    const auto& st = a.stages[v.stage];
    const int xo = at.state[v.agent], uo = at.input[v.agent];
    v.sampled_margin = std::numeric_limits<double>::infinity();
    for (int k = v.step; k <= std::min(T, v.step + v.dwell); ++k) {
      const Box sb = eps_box(a, x[k].segment(xo, a.n()));
      v.sampled_margin = std::min(v.sampled_margin, stage_margin(st, sb, workspace_of(a, sb)));
    }
    t.record(v.sampled_margin, v.step, [&] { return v.name; });
    v.margin = v.sampled_margin;
    if (!b) continue;
    Box g{Eigen::VectorXd(a.n()), Eigen::VectorXd(a.n())};
    for (int k = v.step; k < std::min(T, v.step + v.dwell); ++k) {
      const Eigen::VectorXd xi = x[k].segment(xo, a.n()), ui = u[k].segment(uo, a.m());
      double m = -std::numeric_limits<double>::infinity();
      for (int parts = kFlowParts; parts <= kFlowMaxParts && !(m >= 0); parts *= kFlowRefinement) {
        if (!flow_boxes(*a.dynamics, Box{xi, xi}, ui, Eigen::VectorXd::Zero(a.n()), problem.tau, parts, flow)) break;
        m = std::numeric_limits<double>::infinity();
        for (const Box& f : flow) {
          grow_by_eps(f, a.tube.eps, g);
          m = std::min(m, stage_margin(st, g, workspace_of(a, g)));
        }
      }
      Point p0, p1;
      workspace_point3<double>(*a.dynamics, a.workspace, x[k].data() + xo, p0.data());
      workspace_point3<double>(*a.dynamics, a.workspace, x[k + 1].data() + xo, p1.data());
      b->record(m, k, [&] { return v.name; }, distance2(p1 - p0));
      v.between_margin = std::min(v.between_margin, m);
    }
    v.margin = std::min(v.sampled_margin, v.between_margin);
  }
  return visits;
}

}  // namespace

RobustCheck check_robust(const Problem& problem, const GlobalPlan& plan) {
  return check_robust(problem, plan, schedule_missions(problem, plan.horizon()));
}

RobustCheck check_robust(const Problem& problem, const GlobalPlan& plan, const MissionSchedule& given) {
  return check_robust(problem, plan, given, RobustCheckOptions{});
}

RobustCheck check_robust(const Problem& problem, const GlobalPlan& plan, const MissionSchedule& given,
                         const RobustCheckOptions& options) {
  RobustCheck r;
  const int T = plan.horizon();
  // Knots that are no schedule at this horizon fail the check (named); the stages are then
  // judged at the initial schedule's knots, so that every stage still has a margin.
  const bool mission = std::any_of(problem.agents.begin(), problem.agents.end(), [](const AgentSpec& a) { return !a.stages.empty(); });
  MissionSchedule visits = given;
  const std::string e = mission && given.feasible ? schedule_error(problem, given, T) : std::string();
  if (!mission) {
    visits = schedule_missions(problem, T);
  } else if (given.visit.size() != problem.agents.size() || !e.empty() || given.horizon != T) {
    visits = schedule_missions(problem, T);
    visits.feasible = false;
    visits.why = !e.empty() ? e : !given.why.empty() ? given.why : "the knots are of horizon " + std::to_string(given.horizon) + ", the plan's is " + std::to_string(T);
  }
  const ProductLayout at(problem);
  const auto &xo = at.state, &uo = at.input;
  for (const auto& u : plan.u)
    if (u.size() != uo.back()) {
      r.message = "plan inputs have the wrong dimension";
      r.min_margin = -std::numeric_limits<double>::infinity();
      return r;
    }
  const auto x = rollout(problem, plan.u);
  if (plan.x.size() == x.size())
    for (size_t k = 0; k < x.size(); ++k)
      if (plan.x[k].size() == x[k].size())
        r.max_state_mismatch = std::max(r.max_state_mismatch, (plan.x[k] - x[k]).cwiseAbs().maxCoeff());

  const int N = static_cast<int>(problem.agents.size());
  Tally t, tu;
  std::vector<Point> p;
  std::vector<WorkspaceMargin> m(static_cast<size_t>(problem.body_count()));
  const ObstacleWindows windows(problem, visits);
  for (int k = 0; k <= T; ++k) {
    for (int i = 0; i < N; ++i) {
      const auto& a = problem.agents[i];
      const Eigen::VectorXd xi = x[k].segment(xo[i], a.n());
      const Box X = a.state_bounds.shrunk(a.tube.eps);
      for (int c = 0; c < a.n(); ++c) t.record(inside_margin(X, c, xi[c]), k, [&] { return state_bound_name(a, c); });
      if (k < T) {
        const Eigen::VectorXd ui = plan.u[k].segment(uo[i], a.m());
        for (int c = 0; c < a.m(); ++c)
          tu.record(inside_margin(a.input_bounds, c, ui[c]), k, [&] {
            return "input bound " + a.dynamics->input_names()[c] + " of " + a.name;
          });
      } else {
        const Box G = a.goal.shrunk(a.tube.eps);
        for (int c = 0; c < a.n(); ++c)
          t.record(inside_margin(G, c, xi[c]), k, [&] { return "goal " + a.dynamics->state_names()[c] + " of " + a.name; });
      }
    }
    body_points(problem, xo, x[k].data(), p);
    for (int b = 0; b < problem.body_count(); ++b)
      m[static_cast<size_t>(b)] = margin_at(problem.body_spec(b), x[k].segment(xo[problem.body_agent(b)], problem.body_spec(b).n()));
    for_each_requirement(problem, windows, Moment{k, false}, [&](const Requirement& q) {
      t.record(requirement_margin(problem, q, p, &m), k, [&] { return q.name(problem); }, agents_of(problem, q));
    });
  }
  NamedTally b;
  if (mission) r.stages = check_stages(problem, x, plan.u, visits, t, problem.guarantee == Guarantee::Continuous ? &b : nullptr);
  r.sampled_margin = t.min_;
  r.min_margin = t.min_;
  r.worst = t.name_;
  r.worst_step = t.step_;
  r.worst_agents = t.who_;
  r.min_input_margin = tu.min_;
  r.worst_input = tu.name_;
  if (problem.guarantee == Guarantee::Continuous) {
    r.continuous = true;
    check_between_samples(problem, x, plan.u, windows, options.period_floors, b);
    r.between_shortfalls = b.negative;
    r.between_margin = b.min_;
    r.worst_between = b.name_;
    r.worst_between_step = b.step_;
    if (b.min_ < r.min_margin) {
      r.min_margin = b.min_;
      r.worst = b.name_ + " between steps " + std::to_string(b.step_) + " and " + std::to_string(b.step_ + 1);
      r.worst_step = b.step_;
      r.worst_agents = b.who_;
    }
  }
  r.passed = r.min_margin >= 0.0 && tu.min_ >= 0.0;
  std::ostringstream os;
  os.precision(kMessageDigits);
  os << (r.passed ? "eps-robust" : "NOT eps-robust") << (r.continuous ? " in continuous time" : " at the samples")
     << (r.passed ? ": smallest margin " : ": ") << r.min_margin << " (" << r.worst;
  if (r.worst.find(" between steps ") == std::string::npos) os << " at step " << r.worst_step;
  os << ")";
  if (r.continuous) os << "; at the samples " << r.sampled_margin << ", between them " << r.between_margin;
  if (tu.min_ < 0) os << "; " << r.worst_input << " violated by " << -tu.min_ << " at step " << tu.step_;
  r.message = os.str();
  return r;
}

}  // namespace marsyn::planning
