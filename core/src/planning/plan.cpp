#include "marsyn/core/planning/plan.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "marsyn/core/planning/clearance_rounds.hpp"
#include "marsyn/core/planning/projector.hpp"
#include "marsyn/core/planning/routes.hpp"
#include "marsyn/core/planning/spec_margins.hpp"
#include "marsyn/core/planning/goal_room.hpp"
#include "marsyn/core/planning/workspace_gaps.hpp"
#include "marsyn/number_text.hpp"
#include "marsyn/stopwatch.hpp"

namespace marsyn::planning {

namespace {

// Solvers meet bounds only to their tolerance; clamping keeps U exact and the assembly buffer
// absorbs the resulting state change.
GlobalPlan clamp_and_resimulate(const Problem& problem, const GlobalPlan& raw) {
  const auto uo = ProductLayout(problem).input;
  GlobalPlan out;
  out.tau = problem.tau;
  out.u = raw.u;
  for (auto& u : out.u)
    for (size_t i = 0; i < problem.agents.size(); ++i) {
      const auto& U = problem.agents[i].input_bounds;
      for (int c = 0; c < U.dim(); ++c) {
        double& v = u[uo[i] + c];
        if (!std::isfinite(v)) v = 0.0;
        v = std::clamp(v, U.lo[c], U.hi[c]);
      }
    }
  out.x = rollout(problem, out.u);
  return out;
}

GlobalPlan extend(const Problem& problem, const GlobalPlan& p, int horizon) {
  GlobalPlan w = p;
  const int m = problem.product_input_dim();
  while (static_cast<int>(w.u.size()) < horizon) w.u.push_back(Eigen::VectorXd::Zero(m));
  w.x = rollout(problem, w.u);
  return w;
}

// The largest clearance the assembly keeps between the samples.
double largest_clearance(const Problem& problem, int horizon, const AssemblyOptions& o) {
  double c = 0.0;
  const MissionSchedule visits = schedule_or_initial(problem, o.visits, horizon);
  for (int i = 0; i < static_cast<int>(problem.agents.size()); ++i)
    c = std::max(c, between_clearance(problem, i, visits, horizon, o));
  return c;
}

bool has_stages(const Problem& problem) {
  return std::any_of(problem.agents.begin(), problem.agents.end(), [](const AgentSpec& a) { return !a.stages.empty(); });
}

// A stage of the check short at its knots (a re-timing may find knots the plan can meet).
bool short_at_a_stage(const RobustCheck& c) {
  return std::any_of(c.stages.begin(), c.stages.end(), [](const StageVisit& v) { return !(v.sampled_margin >= 0); });
}

std::string knots_text(const Problem& problem, const MissionSchedule& s) {
  std::string out;
  for (std::size_t i = 0; i < problem.agents.size() && i < s.visit.size(); ++i) {
    if (s.visit[i].empty()) continue;
    out += (out.empty() ? "" : "; ") + problem.agents[i].name + " ";
    for (std::size_t t = 0; t < s.visit[i].size(); ++t) out += (t ? "," : "") + std::to_string(s.visit[i][t]);
  }
  return out;
}

// Robust at the samples and on the inputs, short only between the samples.
bool short_between_only(const RobustCheck& c) {
  return c.continuous && c.sampled_margin >= 0 && c.min_input_margin >= 0 && c.between_margin < 0 &&
         std::isfinite(c.between_margin);
}

// More clearance for exactly the requirements that fell short between the samples: 1.5 times the
// shortfall, and at least half the knot-to-knot motion involved, since a point between two knots
// is within half their distance of one of them (any norm), so that much clearance at the knots
// covers a straight path between them.
void more_clearance(AssemblyOptions& assembly, const RobustCheck& c) {
  for (const auto& [name, m] : c.between_shortfalls) assembly.extra[name] += std::max(1.5 * -m.margin, 0.5 * m.motion);
  assembly.pair_between_extra += crowd_clearance(c);  // a crowd: every pair, growing as the named ones do
}

// The largest number of steps any knot moves from a to b.
int largest_shift(const MissionSchedule& a, const MissionSchedule& b) {
  int d = 0;
  for (std::size_t i = 0; i < a.visit.size() && i < b.visit.size(); ++i)
    for (std::size_t s = 0; s < a.visit[i].size() && s < b.visit[i].size(); ++s)
      d = std::max(d, std::abs(a.visit[i][s] - b.visit[i][s]));
  return d;
}

// The same waypoints (steps and pinned coordinates; NaN where none is pinned).
bool same_waypoints(const std::vector<Waypoint>& p, const std::vector<Waypoint>& q) {
  if (p.size() != q.size()) return false;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p[i].step != q[i].step || p[i].x.size() != q[i].x.size()) return false;
    for (Eigen::Index c = 0; c < p[i].x.size(); ++c)
      if (!(p[i].x[c] == q[i].x[c] || (std::isnan(p[i].x[c]) && std::isnan(q[i].x[c])))) return false;
  }
  return true;
}

// The horizon search of one planner: T, then longer horizons, each warm-started from the last.
// Continuous time: the requirements are imposed between the samples too (the assembly's
// interior points), so a converged plan normally passes the exact check at once. One that is
// robust at its samples and still short between them is re-planned at the same horizon with
// more clearance for the requirements that fell short (a small budget per horizon; clearance
// only grows, so rounds do not undo each other), before a longer horizon is tried. The other
// levers at one horizon, in order: re-timed mission knots, routes around the obstacles,
// another homotopy class, the clearance between the samples dropped.
class HorizonSearch {
 public:
  HorizonSearch(const Problem& problem, const Planner& planner, const PlanSearchOptions& options,
                std::optional<GlobalPlan> warm, const Stopwatch& clock)
      : problem_(problem), planner_(planner), options_(options), clock_(clock), warm_(std::move(warm)),
        assembly_(options.assembly), mission_(has_stages(problem)) {
    best_.check.min_margin = -std::numeric_limits<double>::infinity();
    horizon_ = problem.horizon;
    if (horizon_ <= 0) throw std::invalid_argument("marsyn::planning::plan: the problem's horizon must be positive");
    if (warm_) horizon_ = std::max(horizon_, warm_->horizon());
    visits_ = schedule_or_initial(problem, options.assembly.visits, horizon_);
  }

  PlanOutcome run() {
    int horizons = 0;
    while (horizons < std::max(1, options_.max_attempts)) {
      const double left = options_.time_limit_s - clock_.seconds();
      if (!best_.attempts.empty() && left <= 0) {
        log("time limit reached: no further horizons tried");
        break;
      }
      if (!best_.attempts.empty() && options_.stop && options_.stop()) {
        log("stopped: no further horizons tried");
        break;
      }
      Solved one = solve_once(warm_, left);
      retimed_ = false;
      judge_other_side(one.a);
      judge_routes(one.a);
      note_here(one);
      keep_if_better(one);
      if (best_.feasible) break;
      if (!one.clean.u.empty()) warm_ = one.clean;
      // An obstacle as the worst requirement: the way around it first, then the knots re-timed
      // along the routed plan (re-timing along a plan pressed against an obstacle moves the knots
      // to where it got stuck).
      const bool obstacle_first = one.a.check.worst_agents[0] >= 0 && one.a.check.worst_agents[1] < 0;
      if (more_clearance_between(one.a) || near_miss_again(one) || (obstacle_first && take_routes(one)) || retime_knots(one) ||
          agents_alone_first(one) || take_routes(one) || other_homotopy_class(one) || drop_clearance(one.a))
        continue;
      ++horizons;
      if (horizons >= std::max(1, options_.max_attempts)) {
        // Said, so that a stop with time left is not a mystery.
        log("no robust plan at " + std::to_string(horizons) + " horizon" + (horizons == 1 ? "" : "s") +
            " (up to T = " + std::to_string(horizon_) + "), the most one planning stage tries");
        break;
      }
      if (!longer_horizon_helps()) break;
      here_ = {};
      warm_again_here_ = false;
      retimed_here_ = 0;
      clearance_rounds_.reset();
      horizon_ = std::max(horizon_ + 1, static_cast<int>(std::ceil(horizon_ * options_.horizon_growth)));
      visits_ = schedule_missions(problem_, horizon_);
    }
    if (best_.feasible && mission_) retime_robust_plan();
    return std::move(best_);
  }

 private:
  static constexpr int kRetriesPerHorizon = 2;

  // One solve at the current horizon, assembly and visits: the attempt, the planner's result and
  // the clamped, re-simulated plan.
  struct Solved {
    PlanAttempt a;
    PlanResult res;
    GlobalPlan clean;
    bool routed = false;  // the planner was given routes around the obstacles
  };

  void log(const std::string& line) const {
    if (options_.log) options_.log(line);
  }

  Solved solve_once(const std::optional<GlobalPlan>& from, double left) {
    Solved out;
    assembly_.visits = visits_;
    PlanningProblem pp = assemble(problem_, horizon_, assembly_);
    if (from) pp.warm_start = extend(problem_, *from, horizon_);
    if (routes_) {
      // Beside the stages' own waypoints (their regions' centres at the visits), not instead.
      const auto ways = route_waypoints(problem_, horizon_, visits_, other_side_);
      out.routed = !ways.empty();
      pp.waypoints.insert(pp.waypoints.end(), ways.begin(), ways.end());
      std::stable_sort(pp.waypoints.begin(), pp.waypoints.end(),
                       [](const Waypoint& p, const Waypoint& q) { return p.step < q.step; });
    }
    PlanOptions po;
    po.time_limit_s = std::max(left, 1e-3);
    po.progress = options_.progress;
    out.res = planner_.solve(pp, po);
    PlanAttempt& a = out.a;
    a.planner = planner_.name();
    a.horizon = horizon_;
    a.status = out.res.status;
    a.iterations = out.res.iterations;
    a.solve_time_s = out.res.solve_time_s;
    a.max_violation = out.res.max_violation;
    a.message = out.res.message;
    a.visits = visits_;
    a.retimed = retimed_;
    if (static_cast<int>(out.res.plan.u.size()) == horizon_) {
      out.clean = clamp_and_resimulate(problem_, out.res.plan);
      a.check = check_robust(problem_, out.clean, visits_);
      a.effort = input_effort(problem_, out.clean);
    } else {
      a.check.message = "the planner returned no inputs";
      a.check.min_margin = -std::numeric_limits<double>::infinity();
    }
    if (options_.log) {
      std::ostringstream os;
      os.precision(kMessageDigits);
      // The solver's verdict is its own; when the exact check passes a plan the solver gave up on
      // (the clamped, re-simulated inputs are robust), both are said without contradicting.
      // An approximate plan the exact check passes is the same case: the solver's "no feasible
      // plan found" beside "eps-robust" said two things at once.
      const bool gave_up = out.res.status != PlannerStatus::ExactSolution;
      const std::string verdict = gave_up && a.check.passed ? "stopped short of the solver's own tolerance"
                                                            : std::string(to_string(out.res.status));
      os << (options_.warm_start_planner ? a.planner + " " : std::string()) << "T = " << horizon_ << ": " << verdict
         << " after " << out.res.iterations << " iterations, " << out.res.solve_time_s << " s, violation "
         << out.res.max_violation << "; " << (gave_up && a.check.passed ? "the exact check passes it: " : "")
         << a.check.message;
      if (mission_) os << "; visits " << knots_text(problem_, visits_) << ", input effort " << a.effort;
      // The solver's own account of giving up ("likely infeasible at this horizon") would
      // contradict the exact check that passed the plan; its violation is in the verdict above.
      if (!out.res.message.empty() && !(gave_up && a.check.passed)) os << "; planner: " << out.res.message;
      options_.log(os.str());
    }
    return out;
  }

  void keep_if_better(Solved& one) {
    const PlanAttempt& a = one.a;
    best_.attempts.push_back(a);
    const bool better = best_.attempts.size() == 1 || a.check.passed || a.check.min_margin > best_.check.min_margin;
    if (better && !best_.feasible) {
      best_.extra = assembly_.extra;
      best_.horizon = horizon_;
      best_.result = std::move(one.res);
      best_.check = a.check;
      best_.plan = one.clean;
      best_.visits = visits_;
      best_.feasible = a.check.passed;
    }
  }

  // Robust at the samples, short between them: more clearance for the requirements short there,
  // as often as ClearanceRounds allows at one horizon.
  bool more_clearance_between(const PlanAttempt& a) {
    if (!short_between_only(a.check) || !clearance_rounds_.take(a.check)) return false;
    more_clearance(assembly_, a.check);
    std::ostringstream os;
    os.precision(kMessageDigits);
    os << "robust at the samples, short by " << -a.check.between_margin << " between them (" << a.check.worst_between
       << " after step " << a.check.worst_between_step << "; " << a.check.between_shortfalls.size()
       << " requirement(s) short): re-planning T = " << horizon_ << " with more clearance for them";
    log(os.str());
    return true;
  }

  // A solver that gave up (its penalty at its cap) a hair short of a robust plan: the same
  // horizon once more, warm from that plan, with fresh multipliers and penalties, before any lever
  // that starts over (users2/05's 32 robots: 926 iterations, 25 s, short by 0.021 at one goal; the
  // routes' cold re-plan then took 16 s and did worse). A near miss: short by at most a quarter of
  // the smallest eps of the agents.
  bool near_miss_again(const Solved& one) {
    const PlanAttempt& a = one.a;
    if (warm_again_here_ || one.clean.u.empty() || !std::isfinite(a.check.min_margin) || a.check.min_margin >= 0 ||
        a.status == PlannerStatus::ExactSolution)
      return false;
    double eps = std::numeric_limits<double>::infinity();
    for (const auto& ag : problem_.agents) eps = std::min(eps, ag.tube.eps.minCoeff());
    if (!(-a.check.min_margin <= 0.25 * eps)) return false;
    warm_again_here_ = true;
    log("short by " + number_text(-a.check.min_margin, 3) + " (" + a.check.worst +
        ") after the solver gave up: re-planning T = " + std::to_string(horizon_) + " warm from that plan");
    return true;
  }

  // Short at a stage's knots: the knots re-timed along this plan (where it passes deepest
  // through each region, at an even pace along its path) before anything else is changed.
  // A plan the planner gave up on (infeasible, out of time) is re-timed along once: that finds
  // knots the robot can meet when the schedule asked too much (tests/core/mission_retime); when
  // the re-timed attempt is given up on too, the horizon is short, not the knots (a made-up
  // 3-agent mission spent 3 solves at T = 70, 14_eq_diffdrive_missions_3 three at T = 160 and three
  // at T = 200, each given up on again).
  bool retime_knots(const Solved& one) {
    if (!mission_ || retimed_here_ >= options_.retime_rounds || one.clean.u.empty() || !short_at_a_stage(one.a.check))
      return false;
    const bool solved = one.a.status == PlannerStatus::ExactSolution || one.a.status == PlannerStatus::ApproximateSolution;
    if (!solved && one.a.retimed) return false;
    const MissionSchedule next = retime_missions(problem_, visits_, one.clean.x);
    if (next.visit == visits_.visit) return false;
    ++retimed_here_;
    log("short at a stage's knots: re-planning T = " + std::to_string(horizon_) + " at knots re-timed along the plan (" +
        knots_text(problem_, next) + ")");
    visits_ = next;
    retimed_ = true;
    return true;
  }

  // Short at the samples with agents whose straight way is blocked by obstacles: the local
  // solver may be pressing them into a gap they cannot pass (one too narrow for eps + delta
  // on both sides). The same horizon once more, cold, from routes around the obstacles (the
  // shortest path per agent around the grown obstacles, as waypoints of the reference); later
  // horizons keep the routes.
  bool take_routes(const Solved& one) {
    if (routes_ || routes_dropped_ || !options_.routes || !(one.a.check.sampled_margin < 0) || one.routed) return false;
    const auto ways = route_waypoints(problem_, horizon_, visits_);
    if (ways.empty()) return false;
    routes_ = true;
    routes_judge_ = one.a.check.min_margin;
    warm_.reset();
    log("not robust at the samples, and straight ways cross obstacles: re-planning T = " + std::to_string(horizon_) +
        " from routes around them (" + std::to_string(ways.size()) + " waypoints)");
    return true;
  }

  // A team whose joint solve lost its way (short at the samples, the worst requirement one
  // agent's own: its goal, a bound, an obstacle) while each agent alone may be an easy problem:
  // each agent planned alone at this horizon (the same planner, one attempt, its own obstacles
  // and bodies), their plans side by side as the start of the joint solve; once per
  // planning stage (later attempts start from the best so far, as after any lever). Four bicycles
  // turning left through a junction (tests/problems/users3/intersection.yaml): short by 18.6 at a
  // goal from the straight ways and 21.3 from the routes, 0.007 from the agents' own plans.
  // Not for formations (what the agents do alone says little there), missions (their knots are
  // re-timed along the plan instead, and a re-timed attempt given up on says the horizon is
  // short: tests/core/mission_retime) nor teams past kAloneAgents (a solve each).
  static constexpr std::size_t kAloneAgents = 16;
  bool agents_alone_first(const Solved& one) {
    const auto& w = one.a.check.worst_agents;
    if (alone_tried_ || mission_ || problem_.agents.size() < 2 || problem_.agents.size() > kAloneAgents ||
        !problem_.formation.empty() || !(one.a.check.sampled_margin < 0) || w[1] >= 0)
      return false;
    alone_tried_ = true;
    const ProductLayout lay(problem_);
    GlobalPlan side;
    side.tau = problem_.tau;
    side.u.assign(static_cast<std::size_t>(horizon_), Eigen::VectorXd::Zero(problem_.product_input_dim()));
    side.x.assign(static_cast<std::size_t>(horizon_) + 1, Eigen::VectorXd::Zero(problem_.product_state_dim()));
    for (std::size_t i = 0; i < problem_.agents.size(); ++i) {
      if (options_.stop && options_.stop()) return false;
      Problem alone = problem_;
      alone.agents = {problem_.agents[i]};
      alone.formation.clear();
      alone.extra_bodies.clear();
      for (const auto& e : problem_.extra_bodies)
        if (e.agent == static_cast<int>(i)) alone.extra_bodies.push_back(e), alone.extra_bodies.back().agent = 0;
      alone.horizon = horizon_;
      PlanSearchOptions o;
      o.assembly.buffer = assembly_.buffer;
      o.assembly.inf_norm_corner = assembly_.inf_norm_corner;
      o.assembly.between_points = assembly_.between_points;
      o.assembly.between_clearance = assembly_.between_clearance;
      o.max_attempts = 1;
      o.time_limit_s = std::max(1e-3, (options_.time_limit_s - clock_.seconds()) / static_cast<double>(problem_.agents.size() - i + 1));
      o.routes = options_.routes;
      o.retime_rounds = 0;
      o.stop = options_.stop;
      o.log_closed_gaps = false;
      const PlanOutcome own = HorizonSearch(alone, planner_, o, std::nullopt, clock_).run();
      if (own.plan.horizon() != horizon_ || own.plan.x.size() != side.x.size()) return false;
      for (std::size_t k = 0; k < own.plan.u.size(); ++k) side.u[k].segment(lay.input[i], own.plan.u[k].size()) = own.plan.u[k];
      for (std::size_t k = 0; k < own.plan.x.size(); ++k) side.x[k].segment(lay.state[i], own.plan.x[k].size()) = own.plan.x[k];
    }
    warm_ = side;
    log("short at the samples by " + number_text(-one.a.check.sampled_margin, 3) + " (" + one.a.check.worst +
        "): re-planning T = " + std::to_string(horizon_) + " from each agent's own plan alone, side by side");
    return true;
  }

  // Routes taken and still short at the samples, the worst requirement an agent's (two agents
  // meeting head-on in a lane, say): the same horizon once more, cold, with that agent's route
  // passing the first obstacle on its way on another side (another homotopy class).
  bool other_homotopy_class(const Solved& one) {
    const PlanAttempt& a = one.a;
    if (!routes_ || !one.routed || other_tried_ || !options_.routes || !(a.check.sampled_margin < 0)) return false;
    other_tried_ = true;
    const auto now = route_waypoints(problem_, horizon_, visits_, other_side_);
    for (int who : {a.check.worst_agents[1], a.check.worst_agents[0]}) {
      if (who < 0 || std::find(other_side_.begin(), other_side_.end(), who) != other_side_.end()) continue;
      std::vector<int> flip = other_side_;
      flip.push_back(who);
      if (same_waypoints(route_waypoints(problem_, horizon_, visits_, flip), now)) continue;
      other_before_ = other_side_;
      other_judge_ = a.check.min_margin;
      other_side_ = flip;
      warm_.reset();
      log("not robust at the samples along the routes (" + a.check.worst + "): re-planning T = " +
          std::to_string(horizon_) + " with " + problem_.agents[who].name +
          " passing the first obstacle on its way on the other side (another homotopy class)");
      return true;
    }
    return false;
  }

  // The attempt from the routes decides whether later attempts keep them: routes that did clearly
  // worse than the straight ways (users2/03's tugs: -3.23 against -2.05, and every later solve
  // held to them took 4 times as long) are dropped, and not taken again. A near tie (within 10 %)
  // keeps them, and so does a worst requirement between two agents: another homotopy class,
  // built on the routes, is the next lever then (tests/continuous/one_lane_each.yaml).
  void judge_routes(const PlanAttempt& a) {
    if (!routes_judge_) return;
    const double before = *routes_judge_;
    const bool worse = std::isfinite(before) && !(a.check.min_margin >= before - 0.1 * std::abs(before));
    if (worse && a.check.worst_agents[1] < 0) {
      routes_ = false;
      routes_dropped_ = true;
      log("the routes did worse than the straight ways (" + number_text(a.check.min_margin, 3) + " against " +
          number_text(*routes_judge_, 3) + "): later attempts start without them");
    }
    routes_judge_.reset();
  }

  // The attempt after a change of homotopy class decides whether later horizons keep it.
  void judge_other_side(const PlanAttempt& a) {
    if (!other_judge_) return;
    if (!(a.check.min_margin > *other_judge_)) other_side_ = other_before_;
    other_judge_.reset();
  }

  // The clearance between the samples is sized for moving agents; a plan that must end (or
  // wait) pressed against a requirement cannot keep it. Before a longer horizon, the same one
  // once without it (the exact check and the targeted re-plans above then decide), when the
  // shortfall at the samples is one the clearance could explain.
  bool drop_clearance(const PlanAttempt& a) {
    if (clearance_dropped_ || !(assembly_.between_clearance > 0) || !(a.check.sampled_margin < 0) ||
        !(-a.check.sampled_margin <= largest_clearance(problem_, horizon_, assembly_)) ||
        problem_.guarantee != Guarantee::Continuous)
      return false;
    clearance_dropped_ = true;
    assembly_.between_clearance = 0.0;
    log("not robust at the samples with the clearance between them: re-planning T = " + std::to_string(horizon_) +
        " without it");
    return true;
  }

  // The best attempt at the current horizon (its plan kept to judge what limits it).
  void note_here(const Solved& one) {
    if (one.clean.u.empty() || (here_.plan.has_value() && !(one.a.check.sampled_margin > here_.check.sampled_margin)))
      return;
    here_.check = one.a.check;
    here_.plan = one.clean;
  }

  // Horizon policy (issue 49): a longer horizon gives the agents time, which helps only when time
  // is what the failure lacked. Judged on this horizon's best attempt, in order:
  // - the worst shortfall is a stage pinned at the end of its window (its knot is its `by`): the
  //   window, not the horizon, is what blocks (the steps before it do not change with T); no
  //   longer horizon is tried;
  // - an agent short of its goal or a stage while its inputs sit at a bound of U on a quarter of
  //   the steps or more: speed or input limits it; a longer horizon is tried (and said why);
  // - the same requirement falls short as at the previous horizon, by about as much (within 10 %):
  //   the longer horizon did not help, a longer still will not either.
  // Otherwise a longer horizon is tried. A stop is said with its numbers and kept in
  // PlanOutcome::horizon_blocked, so the outer search does not lengthen the horizon either.
  bool longer_horizon_helps() {
    if (!here_.plan) return true;
    const RobustCheck& c = here_.check;
    const ProductLayout layout(problem_);
    const std::string T = std::to_string(horizon_);
    for (const auto& v : c.stages) {
      const MissionStage& st = problem_.agents[static_cast<std::size_t>(v.agent)].stages[static_cast<std::size_t>(v.stage)];
      if (!(v.sampled_margin < 0) || st.by < 0 || v.step < st.by || !(v.sampled_margin <= c.sampled_margin + 1e-12)) continue;
      std::ostringstream os;
      os.precision(kMessageDigits);
      os << v.name << " must be reached by " << st.by * problem_.tau << " s (step " << st.by << "); the plan at T = " << T
         << " falls short there by " << -v.sampled_margin
         << ": a longer horizon does not move the window (a later `by`, fewer stages before it, a faster agent or a "
            "start nearer the region can)";
      return blocked(os.str());
    }
    for (std::size_t i = 0; i < problem_.agents.size(); ++i) {
      const AgentSpec& a = problem_.agents[i];
      bool short_here = goal_margin(a, here_.plan->x.back(), layout.state[i]) < 0;
      for (const auto& v : c.stages) short_here = short_here || (v.agent == static_cast<int>(i) && v.sampled_margin < 0);
      if (!short_here) continue;
      std::vector<Eigen::VectorXd> u;
      for (const auto& uk : here_.plan->u) u.push_back(uk.segment(layout.input[i], a.input_bounds.dim()));
      const double share = saturation_share(u, a.input_bounds);
      if (share >= 0.25) {
        log("at T = " + T + " " + a.name + " falls short with its inputs at a bound of U on " +
            std::to_string(static_cast<int>(std::lround(100 * share))) +
            " % of the steps: speed or input limits it, so a longer horizon gives it time");
        last_short_ = {c.worst, c.min_margin};
        return true;
      }
    }
    const bool same = last_short_ && last_short_->first == c.worst && c.sampled_margin < 0 &&
                      std::isfinite(c.min_margin) &&
                      std::abs(c.min_margin - last_short_->second) <= 0.1 * std::abs(last_short_->second);
    if (same) {
      std::ostringstream os;
      os.precision(kMessageDigits);
      os << "the plans at the last two horizons fall short at the same requirement (" << c.worst << ", by "
         << -last_short_->second << " and " << -c.min_margin
         << ") with their inputs inside U: a longer horizon does not help here";
      return blocked(os.str());
    }
    if (c.sampled_margin < 0) last_short_ = {c.worst, c.min_margin};
    return true;
  }

  bool blocked(const std::string& why) {
    log(why);
    best_.horizon_blocked = why;
    return false;
  }

  // How deep the agent's final state lies in its goal shrunk by eps (negative: missed).
  static double goal_margin(const AgentSpec& a, const Eigen::VectorXd& x, int offset) {
    const Box G = a.goal.shrunk(a.tube.eps);
    double m = std::numeric_limits<double>::infinity();
    for (int c = 0; c < G.dim(); ++c) m = std::min(m, inside_margin(G, c, x[offset + c]));
    return m;
  }

  // A robust plan: its knots re-timed along it and the same horizon solved again from it, kept
  // only when robust with less input effort (the exact check judges, the effort compares).
  void retime_robust_plan() {
    horizon_ = best_.horizon;
    double effort = input_effort(problem_, best_.plan);
    std::vector<MissionSchedule> tried{best_.visits};
    for (int r = 0; r < options_.retime_rounds; ++r) {
      const double left = options_.time_limit_s - clock_.seconds();
      if (left <= 0 || (options_.stop && options_.stop())) break;
      const MissionSchedule next = retime_missions(problem_, best_.visits, best_.plan.x);
      // Knots that move a step or two are the plan's own jitter: a re-solve for them costs a
      // solve and changes the effort by little (warehouse.yaml: `git show f9b6c78:docs/benchmarks.md`,
      // "Missions: the plan's visit knots"). Knots that
      // come back near ones already solved for oscillate (the rendezvous: 51, 45, then 49).
      const int jitter = std::max(2, horizon_ / 40);
      if (std::any_of(tried.begin(), tried.end(), [&](const MissionSchedule& s) { return largest_shift(s, next) < jitter; }))
        break;
      tried.push_back(next);
      visits_ = next;
      retimed_ = true;
      assembly_.extra = best_.extra;
      // Said first: this round's solves try to lower the effort of a plan already found.
      log("robust plan found; re-timing round " + std::to_string(r + 1) + ": knots re-timed along it (" +
          knots_text(problem_, next) + "), T = " + std::to_string(horizon_) +
          " solved again from it, kept only if robust with less input effort");
      Solved one = solve_once(best_.plan, left);
      best_.attempts.push_back(one.a);
      // Short only between the samples: more clearance at the same knots, as in the search.
      for (int retry = 0; retry < kRetriesPerHorizon && short_between_only(one.a.check) &&
                          options_.time_limit_s - clock_.seconds() > 0;
           ++retry) {
        more_clearance(assembly_, one.a.check);
        log("re-timed plan short by " + number_text(-one.a.check.between_margin, 3) +
            " between the samples: the same knots again with more clearance for the requirements short there");
        one = solve_once(one.clean, options_.time_limit_s - clock_.seconds());
        best_.attempts.push_back(one.a);
      }
      const bool keep = one.a.check.passed && one.a.effort < effort;
      log(std::string(keep ? "re-timed knots kept" : "re-timed knots not kept") + " (input effort " +
          number_text(effort) + " -> " + number_text(one.a.effort) + (one.a.check.passed ? "" : ", not robust") +
          ")");
      if (!keep) break;
      effort = one.a.effort;
      best_.extra = assembly_.extra;
      best_.result = std::move(one.res);
      best_.check = one.a.check;
      best_.plan = one.clean;
      best_.visits = visits_;
    }
  }

  const Problem& problem_;
  const Planner& planner_;
  const PlanSearchOptions& options_;
  const Stopwatch& clock_;
  std::optional<GlobalPlan> warm_;
  PlanOutcome best_;
  AssemblyOptions assembly_;
  const bool mission_;
  int horizon_ = 0;
  // The visit knots: the given ones when they are a schedule at the first horizon, else the
  // initial schedule; re-timed along the plans (retime_missions) at most retime_rounds times per
  // horizon; a longer horizon starts again from the initial schedule.
  MissionSchedule visits_;
  int retimed_here_ = 0;
  ClearanceRounds clearance_rounds_;
  bool warm_again_here_ = false;  // a near miss re-planned warm at this horizon
  bool clearance_dropped_ = false, routes_ = false, retimed_ = false, other_tried_ = false, alone_tried_ = false;
  // Agents whose routes pass the first obstacle on their way on another side than the shortest
  // (another homotopy class), and the margin of the attempt before that change while it is
  // still to be judged (kept for later horizons only when the new class did better).
  std::vector<int> other_side_, other_before_;
  std::optional<double> other_judge_;
  // The margin of the attempt before the routes were taken, while the routed one is to be judged.
  std::optional<double> routes_judge_;
  bool routes_dropped_ = false;
  // The best attempt at the current horizon, and the worst requirement (with its margin at the
  // samples) of the last horizon that fell short, for the horizon policy.
  struct {
    RobustCheck check;
    std::optional<GlobalPlan> plan;
  } here_;
  std::optional<std::pair<std::string, double>> last_short_;
};

PlanOutcome search(const Problem& problem, const Planner& planner, const PlanSearchOptions& options,
                   std::optional<GlobalPlan> warm, const Stopwatch& clock) {
  return HorizonSearch(problem, planner, options, std::move(warm), clock).run();
}

}  // namespace

double saturation_share(const std::vector<Eigen::VectorXd>& u, const Box& b) {
  if (u.empty() || b.dim() == 0) return 0.0;
  int at = 0;
  for (const auto& uk : u) {
    bool sat = false;
    for (Eigen::Index j = 0; j < uk.size() && j < b.dim(); ++j) {
      const double tol = 1e-6 * (b.hi[j] - b.lo[j]);
      sat = sat || uk[j] <= b.lo[j] + tol || uk[j] >= b.hi[j] - tol;
    }
    at += sat ? 1 : 0;
  }
  return static_cast<double>(at) / static_cast<double>(u.size());
}

PlanOutcome plan(const Problem& problem, const Planner& planner, const PlanSearchOptions& options) {
  const Stopwatch clock;
  // Starts closer than the tubes allow, and goals that leave the tubes no room, fail the robust
  // check whatever the planner does: say so at once instead of solving at every horizon (a
  // 100-agent solve takes minutes).
  std::optional<PlanOutcome> hopeless;
  auto refuse = [&](const auto& found, std::size_t count, const std::string& what, const std::string& many) {
    if (found.empty() || hopeless) return;
    hopeless.emplace();
    hopeless->check.min_margin = -std::numeric_limits<double>::infinity();
    hopeless->check.message = "no eps-robust plan at any horizon: " + describe(found.front(), problem) +
                              (count > 1 ? " (" + std::to_string(count) + " " + many + ")" : std::string());
    if (options.log)
      for (const auto& c : found) options.log(what + ": " + describe(c, problem));
    hopeless->total_time_s = clock.seconds();
  };
  std::size_t starts = 0, goals = 0;
  const auto crowded = crowded_starts(problem, 3, &starts);
  refuse(crowded, starts, "crowded start", "crowded starts");
  if (!hopeless) {
    const auto cramped = crowded_goals(problem, 3, &goals);
    refuse(cramped, goals, "goal without room", "goals without room");
  }
  if (hopeless) return *hopeless;
  std::optional<GlobalPlan> warm = options.warm_start;
  if (warm && warm->u.empty()) warm.reset();
  PlanOutcome first;
  if (options.warm_start_planner) {
    first = search(problem, *options.warm_start_planner, options, warm, clock);
    if (!first.plan.u.empty()) warm = first.plan;
    if (options.log)
      options.log(options.warm_start_planner->name() + " -> " + planner.name() + ": " +
                  (first.plan.u.empty() ? "no plan to start from, " + planner.name() + " starts cold"
                                        : std::string(first.feasible ? "robust" : "best non-robust") + " plan (T = " +
                                              std::to_string(first.horizon) + ") as the warm start"));
  }
  // The first planner's knots start the main planner, with its plan.
  PlanSearchOptions main = options;
  if (options.warm_start_planner && !first.plan.u.empty()) main.assembly.visits = first.visits;
  PlanOutcome best = search(problem, planner, main, warm, clock);
  if (options.warm_start_planner) {
    std::vector<PlanAttempt> all = first.attempts;
    all.insert(all.end(), best.attempts.begin(), best.attempts.end());
    // The first planner's robust plan passed the same exact check: better than none at all.
    if (!best.feasible && first.feasible) {
      if (options.log)
        options.log(planner.name() + " found no robust plan; keeping " + options.warm_start_planner->name() + "'s");
      best = std::move(first);
    }
    best.attempts = std::move(all);
  }
  if (!best.plan.u.empty()) best.nominal = ProductProjector().project(problem, best.plan);
  // A gap closed at every horizon explains a failure better than "try a longer horizon".
  if (!best.feasible && options.log && options.log_closed_gaps) {
    const auto gaps = gaps_on_the_way(problem);
    // A field of many (crop beds, shelves) is one cause: grouped beyond three, `check` lists them.
    if (gaps.size() > 3) {
      const auto narrowest = std::min_element(gaps.begin(), gaps.end(), [](const NarrowGap& a, const NarrowGap& b) {
        return a.width < b.width;
      });
      std::ostringstream os;
      os.precision(kMessageDigits);
      os << gaps.size() << " closed gaps (`marsyn check` lists them), the narrowest: " << describe(*narrowest)
         << "; a longer horizon cannot open them (a route around them, a smaller eps or delta can)";
      options.log(os.str());
    } else {
      for (const auto& gap : gaps)
        options.log("closed gap: " + describe(gap) + "; a longer horizon cannot open it (a route around it, a smaller "
                    "eps or delta can)");
    }
  }
  best.total_time_s = clock.seconds();
  return best;
}

double input_effort(const Problem& problem, const GlobalPlan& plan) {
  const auto uo = ProductLayout(problem).input;
  double e = 0.0;
  for (const auto& u : plan.u)
    for (std::size_t i = 0; i < problem.agents.size(); ++i) {
      const Box& U = problem.agents[i].input_bounds;
      for (int c = 0; c < U.dim(); ++c) {
        const double scale = std::max(std::abs(U.lo[c]), std::abs(U.hi[c]));
        if (scale > 0 && std::isfinite(scale)) e += std::pow(u[uo[i] + c] / scale, 2) * problem.tau;
      }
    }
  return e;
}

std::string summary(const Problem& problem, const PlanOutcome& o) {
  std::ostringstream os;
  os.precision(kMessageDigits);
  os << "problem " << (problem.name.empty() ? "(unnamed)" : problem.name) << ": " << problem.agents.size()
     << " agents, " << problem.product_state_dim() << " states, " << problem.product_input_dim() << " inputs\n";
  for (const auto& a : o.attempts)
    os << "  " << (a.planner.empty() ? "" : a.planner + " ") << "T = " << a.horizon << ": " << to_string(a.status)
       << ", " << a.iterations << " iterations, "
       << a.solve_time_s << " s, solver violation " << a.max_violation << ", "
       << (a.check.passed ? "robust" : "not robust") << " (margin " << a.check.min_margin << ")\n";
  os << (o.feasible ? "FEASIBLE" : "NO FEASIBLE PLAN") << ": horizon " << o.horizon << ", total " << o.total_time_s
     << " s\n  " << o.check.message << "\n";
  if (has_stages(problem) && !o.visits.empty())
    os << "  visit knots: " << knots_text(problem, o.visits) << " (initial guess: "
       << knots_text(problem, schedule_missions(problem, o.visits.horizon)) << ")\n";
  if (!o.feasible && !o.horizon_blocked.empty()) os << "  no longer horizon tried: " << o.horizon_blocked << "\n";
  if (!o.feasible)
    for (const auto& gap : gaps_on_the_way(problem))
      os << "  closed gap: " << describe(gap) << " (a longer horizon cannot open it)\n";
  return os.str();
}

}  // namespace marsyn::planning
