// assemble(): the eps-robust specification over a horizon as named constraints on the product
// state, and the product layout the constraints are written in.
#include "marsyn/core/planning/constraints.hpp"
#include "marsyn/core/planning/mission.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace marsyn::planning {


double between_clearance(const Problem& problem, int agent, const MissionSchedule& visits, int horizon,
                         const AssemblyOptions& opt) {
  if (opt.between_points <= 0) return 0.0;
  const AgentSpec& a = problem.agents[static_cast<std::size_t>(agent)];
  const double leg = agent < static_cast<int>(visits.visit.size())
                         ? fastest_leg_speed(a, visits.visit[static_cast<std::size_t>(agent)], horizon, problem.tau)
                         : 0.0;  // 0 without stages too
  return opt.between_clearance * problem.tau / (opt.between_points + 1) * workspace_speed_bound(a, problem.tau * horizon, leg);
}

namespace {

// assemble()'s work: the product's bounds, x0 and goal, then the requirements as constraints at
// the knots, the missions' stages, and the rows between the samples.
class Assembly {
 public:
  Assembly(const Problem& problem, int horizon, const AssemblyOptions& opt)
      : problem_(problem), horizon_(horizon), opt_(opt), N_(static_cast<int>(problem.agents.size())),
        xo_(ProductLayout(problem).state), uo_(ProductLayout(problem).input) {}

  PlanningProblem run() {
    bounds();  // first: it refuses an agent of inconsistent dimensions
    sched_ = schedule_or_initial(problem_, opt_.visits, horizon_);
    windows_ = ObstacleWindows(problem_, sched_);
    requirements(std::vector<double>(N_, 0.0), pp_.constraints);
    if (std::any_of(problem_.agents.begin(), problem_.agents.end(), [](const AgentSpec& a) { return !a.stages.empty(); }))
      stages();
    if (problem_.guarantee == Guarantee::Continuous && opt_.between_points > 0) between();
    return std::move(pp_);
  }

 private:
  double more(const std::string& name) const {
    const auto it = opt_.extra.find(name);
    return it == opt_.extra.end() ? 0.0 : it->second;
  }

  // x0, the state bounds and the goal shrunk by eps (and any clearance by name), U, and each
  // agent's margin table.
  void bounds() {
    const int n = xo_.back(), m = uo_.back();
    pp_.problem = &problem_;
    pp_.horizon = horizon_;
    pp_.x0.resize(n);
    pp_.input_bounds = {Eigen::VectorXd(m), Eigen::VectorXd(m)};
    pp_.state_bounds = {Eigen::VectorXd(n), Eigen::VectorXd(n)};
    pp_.goal = {Eigen::VectorXd(n), Eigen::VectorXd(n)};
    margin_.resize(static_cast<size_t>(problem_.body_count()));
    for (int i = 0; i < N_; ++i) {
      const auto& a = problem_.agents[i];
      if (a.dynamics == nullptr || a.dynamics->state_dim() != a.n() || a.dynamics->input_dim() != a.m() ||
          a.tube.eps.size() != a.n() || a.state_bounds.dim() != a.n() || a.goal.dim() != a.n())
        throw std::invalid_argument("marsyn::planning::assemble: inconsistent dimensions for agent " + a.name);
      const Eigen::VectorXd shrink = a.tube.eps.array() + opt_.buffer;
      Eigen::VectorXd shrink_x = shrink;
      for (int c = 0; c < a.n(); ++c) shrink_x[c] += more(state_bound_name(a, c));
      const Box X = a.state_bounds.shrunk(shrink_x);
      pp_.x0.segment(xo_[i], a.n()) = a.x0;
      const Box G = a.goal.shrunk(shrink);
      pp_.state_bounds.lo.segment(xo_[i], a.n()) = X.lo;
      pp_.state_bounds.hi.segment(xo_[i], a.n()) = X.hi;
      pp_.goal.lo.segment(xo_[i], a.n()) = G.lo;
      pp_.goal.hi.segment(xo_[i], a.n()) = G.hi;
      pp_.input_bounds.lo.segment(uo_[i], a.m()) = a.input_bounds.lo;
      pp_.input_bounds.hi.segment(uo_[i], a.m()) = a.input_bounds.hi;
      margin_[i] = std::make_shared<MarginTable>(a, a.state_bounds.shrunk(a.tube.eps));
    }
    // Further bodies: how far each one's point moves inside its agent's tube.
    for (int b = N_; b < problem_.body_count(); ++b) {
      const AgentSpec& body = problem_.body_spec(b);
      margin_[static_cast<size_t>(b)] = std::make_shared<MarginTable>(body, body.state_bounds.shrunk(body.tube.eps));
    }
  }

  // The requirements once; `clear[i]` is agent i's clearance beyond the buffer (0 at the knots).
  void requirements(const std::vector<double>& clear, std::vector<std::shared_ptr<const Constraint>>& out) {
    const bool inf = problem_.delta_norm == Norm::Inf;
    // The larger of the two, not the sum: the relative motion reaches the sum only when both
    // move at full speed against each other, and the band of a formation is narrow.
    const double crowd = &out == &pp_.between ? opt_.pair_between_extra : 0.0;
    auto pair_clear = [&](int i, int j) { return std::max(clear[i], clear[j]); };
    // Obstacles and pairs are of body slots (the agents' first bodies, then the further ones:
    // Problem::body_count); a slot's state is its agent's.
    const int B = problem_.body_count();
    for (int s = 0; s < B; ++s) {
      const int i = problem_.body_agent(s);
      const auto& a = problem_.body_spec(s);
      for (size_t o = 0; o < problem_.obstacles.size(); ++o) {
        const auto& obs = problem_.obstacles[o];
        // A staged obstacle binds at its window's knots only. Between them the planners, whose
        // interior points apply at every period, do not see it: the exact check holds the
        // continuous nominal to it and a shortfall comes back as clearance by name (as for a
        // dwell), so its knots keep the clearance between the samples would need.
        std::vector<int> steps;
        if (obs.staged) {
          if (&out == &pp_.between) continue;
          steps = windows_.knots(i, static_cast<int>(o));
          if (steps.empty()) continue;
        }
        const std::string name = obstacle_name(problem_, static_cast<int>(o), a);
        const double od = problem_.obstacle_clearance(s);
        auto c = std::make_shared<ObstacleConstraint>(name, a, xo_[i], obs.vertices, margin_[s], inf ? od : 0.0,
                                                      (inf ? 0.0 : od) + opt_.buffer + clear[i] + more(name),
                                                      problem_.distance_model);
        c->set_z(obs.z_lo, obs.z_hi);
        if (obs.staged) c->bind_only_at(std::move(steps));
        out.push_back(std::move(c));
      }
    }
    if (problem_.pairwise_collision)
      for (int s = 0; s < B; ++s)
        for (int t = s + 1; t < B; ++t) {
          const int i = problem_.body_agent(s), j = problem_.body_agent(t);
          if (i == j) continue;  // one agent's own bodies
          const auto &a = problem_.body_spec(s), &b = problem_.body_spec(t);
          const std::string name = collision_name(a, b);
          out.push_back(std::make_shared<PairConstraint>(name, a, xo_[i], b, xo_[j], problem_.delta_norm, problem_.pair_clearance(s, t),
                                                         margin_[s], margin_[t], opt_.inf_norm_corner,
                                                         opt_.buffer + pair_clear(i, j) + crowd + more(name)));
        }
    for (const auto& f : problem_.formation) {
      if (f.i < 0 || f.j < 0 || f.i >= N_ || f.j >= N_ || f.i == f.j)
        throw std::invalid_argument("marsyn::planning::assemble: formation pair with a bad agent index");
      const auto &a = problem_.agents[f.i], &b = problem_.agents[f.j];
      const std::string name = formation_name(a, b);
      out.push_back(std::make_shared<FormationConstraint>(name, a, xo_[f.i], b, xo_[f.j], f.lambda, f.mu, margin_[f.i],
                                                          margin_[f.j], opt_.buffer + pair_clear(f.i, f.j) + more(name)));
    }
  }

  // Missions (docs/tasks.md): each stage's region, shrunk by eps, at its visit knots.
  // Between the dwell's knots the exact check holds the continuous nominal to the region, and a
  // shortfall there comes back as clearance for the stage by name (AssemblyOptions::extra).
  void stages() {
    const int n = xo_.back();
    for (int i = 0; i < N_; ++i) {
      const auto& a = problem_.agents[i];
      for (int s = 0; s < static_cast<int>(a.stages.size()); ++s) {
        std::vector<int> steps;
        for (int k = sched_.visit[i][s]; k <= std::min(horizon_, sched_.visit[i][s] + a.stages[s].dwell); ++k)
          steps.push_back(k);
        const std::string name = stage_name(a, s);
        pp_.constraints.push_back(std::make_shared<StageConstraint>(name, a, xo_[i], s, steps, opt_.buffer + more(name)));
        for (int k : steps) pp_.waypoints.push_back({k, stage_waypoint(a, s, xo_[i], n)});
      }
    }
    std::stable_sort(pp_.waypoints.begin(), pp_.waypoints.end(),
                     [](const Waypoint& p, const Waypoint& q) { return p.step < q.step; });
  }

  // Between the samples: the state bounds and the requirements at the interior points, with the
  // clearance an agent's speed needs between them.
  void between() {
    pp_.between_points = opt_.between_points;
    std::vector<double> clear(N_);
    for (int i = 0; i < N_; ++i) {
      const auto& a = problem_.agents[i];
      clear[i] = between_clearance(problem_, i, sched_, horizon_, opt_);
      pp_.between.push_back(std::make_shared<StateBoxConstraint>(
          "state bounds of " + a.name, xo_[i],
          Box{pp_.state_bounds.lo.segment(xo_[i], a.n()), pp_.state_bounds.hi.segment(xo_[i], a.n())}));
    }
    requirements(clear, pp_.between);
  }

  const Problem& problem_;
  const int horizon_;
  const AssemblyOptions& opt_;
  const int N_;
  const std::vector<int> xo_, uo_;
  MissionSchedule sched_;  // the visit knots the stages and staged obstacles bind at
  ObstacleWindows windows_;
  PlanningProblem pp_;
  std::vector<std::shared_ptr<const MarginTable>> margin_;
};

}  // namespace

PlanningProblem assemble(const Problem& problem, int horizon, const AssemblyOptions& opt) {
  if (problem.agents.empty()) throw std::invalid_argument("marsyn::planning::assemble: the problem has no agents");
  if (horizon <= 0) throw std::invalid_argument("marsyn::planning::assemble: horizon must be positive");
  return Assembly(problem, horizon, opt).run();
}

}  // namespace marsyn::planning
