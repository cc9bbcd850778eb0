// assemble(): the eps-robust specification over a horizon as named constraints on the product
// state, and the product layout the constraints are written in.
#include "marsyn/core/planning/constraints.hpp"
#include "marsyn/core/planning/mission.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace marsyn::planning {

std::vector<int> state_offsets(const Problem& problem) { return ProductLayout(problem).state; }

std::vector<int> input_offsets(const Problem& problem) { return ProductLayout(problem).input; }


double between_clearance(const Problem& problem, const AgentSpec& a, int horizon, const AssemblyOptions& opt) {
  if (opt.between_points <= 0) return 0.0;
  return opt.between_clearance * problem.tau / (opt.between_points + 1) * workspace_speed_bound(a, problem.tau * horizon);
}

PlanningProblem assemble(const Problem& problem, int horizon, const AssemblyOptions& opt) {
  const int N = static_cast<int>(problem.agents.size());
  if (N == 0) throw std::invalid_argument("marsyn::planning::assemble: the problem has no agents");
  if (horizon <= 0) throw std::invalid_argument("marsyn::planning::assemble: horizon must be positive");
  const auto xo = state_offsets(problem), uo = input_offsets(problem);
  const int n = xo.back(), m = uo.back();
  PlanningProblem pp;
  pp.problem = &problem;
  pp.horizon = horizon;
  pp.x0.resize(n);
  pp.input_bounds = {Eigen::VectorXd(m), Eigen::VectorXd(m)};
  pp.state_bounds = {Eigen::VectorXd(n), Eigen::VectorXd(n)};
  pp.goal = {Eigen::VectorXd(n), Eigen::VectorXd(n)};
  std::vector<std::shared_ptr<const MarginTable>> margin(N);
  auto more = [&](const std::string& name) {
    const auto it = opt.extra.find(name);
    return it == opt.extra.end() ? 0.0 : it->second;
  };
  for (int i = 0; i < N; ++i) {
    const auto& a = problem.agents[i];
    if (a.dynamics == nullptr || a.dynamics->state_dim() != a.n() || a.dynamics->input_dim() != a.m() ||
        a.tube.eps.size() != a.n() || a.state_bounds.dim() != a.n() || a.goal.dim() != a.n())
      throw std::invalid_argument("marsyn::planning::assemble: inconsistent dimensions for agent " + a.name);
    const Eigen::VectorXd shrink = a.tube.eps.array() + opt.buffer;
    Eigen::VectorXd shrink_x = shrink;
    for (int c = 0; c < a.n(); ++c) shrink_x[c] += more(state_bound_name(a, c));
    const Box X = a.state_bounds.shrunk(shrink_x);
    pp.x0.segment(xo[i], a.n()) = a.x0;
    const Box G = a.goal.shrunk(shrink);
    pp.state_bounds.lo.segment(xo[i], a.n()) = X.lo;
    pp.state_bounds.hi.segment(xo[i], a.n()) = X.hi;
    pp.goal.lo.segment(xo[i], a.n()) = G.lo;
    pp.goal.hi.segment(xo[i], a.n()) = G.hi;
    pp.input_bounds.lo.segment(uo[i], a.m()) = a.input_bounds.lo;
    pp.input_bounds.hi.segment(uo[i], a.m()) = a.input_bounds.hi;
    margin[i] = std::make_shared<MarginTable>(a, a.state_bounds.shrunk(a.tube.eps));
  }
  const double delta = problem.delta;
  const bool inf = problem.delta_norm == Norm::Inf;
  const MissionSchedule sched = schedule_or_initial(problem, opt.visits, horizon);
  const ObstacleWindows windows(problem, sched);
  // The requirements once; `clear[i]` is agent i's clearance beyond the buffer (0 at the knots).
  auto requirements = [&](const std::vector<double>& clear, std::vector<std::shared_ptr<const Constraint>>& out) {
    // The larger of the two, not the sum: the relative motion reaches the sum only when both
    // move at full speed against each other, and the band of a formation is narrow.
    auto pair_clear = [&](int i, int j) { return std::max(clear[i], clear[j]); };
    for (int i = 0; i < N; ++i) {
      const auto& a = problem.agents[i];
      for (size_t o = 0; o < problem.obstacles.size(); ++o) {
        const auto& obs = problem.obstacles[o];
        // A staged obstacle binds at its window's knots only. Between them the planners, whose
        // interior points apply at every period, do not see it: the exact check holds the
        // continuous nominal to it and a shortfall comes back as clearance by name (as for a
        // dwell), so its knots keep the clearance between the samples would need.
        std::vector<int> steps;
        if (obs.staged) {
          if (&out == &pp.between) continue;
          steps = windows.knots(i, static_cast<int>(o));
          if (steps.empty()) continue;
        }
        const std::string name = obstacle_name(problem, static_cast<int>(o), a);
        auto c = std::make_shared<ObstacleConstraint>(name, a, xo[i], obs.vertices, margin[i], inf ? delta : 0.0,
                                                      (inf ? 0.0 : delta) + opt.buffer + clear[i] + more(name),
                                                      problem.distance_model);
        c->set_z(obs.z_lo, obs.z_hi);
        if (obs.staged) c->bind_only_at(std::move(steps));
        out.push_back(std::move(c));
      }
    }
    if (problem.pairwise_collision)
      for (int i = 0; i < N; ++i)
        for (int j = i + 1; j < N; ++j) {
          const auto &a = problem.agents[i], &b = problem.agents[j];
          const std::string name = collision_name(a, b);
          out.push_back(std::make_shared<PairConstraint>(name, a, xo[i], b, xo[j], problem.delta_norm, delta, margin[i],
                                                         margin[j], opt.inf_norm_corner,
                                                         opt.buffer + pair_clear(i, j) + more(name)));
        }
    for (const auto& f : problem.formation) {
      if (f.i < 0 || f.j < 0 || f.i >= N || f.j >= N || f.i == f.j)
        throw std::invalid_argument("marsyn::planning::assemble: formation pair with a bad agent index");
      const auto &a = problem.agents[f.i], &b = problem.agents[f.j];
      const std::string name = formation_name(a, b);
      out.push_back(std::make_shared<FormationConstraint>(name, a, xo[f.i], b, xo[f.j], f.lambda, f.mu, margin[f.i],
                                                          margin[f.j], opt.buffer + pair_clear(f.i, f.j) + more(name)));
    }
  };
  requirements(std::vector<double>(N, 0.0), pp.constraints);
  // Missions (docs/tasks.md): each stage's region, shrunk by eps, at its visit knots.
  // Between the dwell's knots the exact check holds the continuous nominal to the region, and a
  // shortfall there comes back as clearance for the stage by name (AssemblyOptions::extra).
  if (std::any_of(problem.agents.begin(), problem.agents.end(), [](const AgentSpec& a) { return !a.stages.empty(); })) {
    for (int i = 0; i < N; ++i) {
      const auto& a = problem.agents[i];
      for (int s = 0; s < static_cast<int>(a.stages.size()); ++s) {
        std::vector<int> steps;
        for (int k = sched.visit[i][s]; k <= std::min(horizon, sched.visit[i][s] + a.stages[s].dwell); ++k) steps.push_back(k);
        const std::string name = stage_name(a, s);
        pp.constraints.push_back(std::make_shared<StageConstraint>(name, a, xo[i], s, steps, opt.buffer + more(name)));
        for (int k : steps) pp.waypoints.push_back({k, stage_waypoint(a, s, xo[i], n)});
      }
    }
    std::stable_sort(pp.waypoints.begin(), pp.waypoints.end(), [](const Waypoint& p, const Waypoint& q) { return p.step < q.step; });
  }
  if (problem.guarantee == Guarantee::Continuous && opt.between_points > 0) {
    pp.between_points = opt.between_points;
    std::vector<double> clear(N);
    for (int i = 0; i < N; ++i) {
      const auto& a = problem.agents[i];
      clear[i] = between_clearance(problem, a, horizon, opt);
      pp.between.push_back(std::make_shared<StateBoxConstraint>(
          "state bounds of " + a.name, xo[i], Box{pp.state_bounds.lo.segment(xo[i], a.n()), pp.state_bounds.hi.segment(xo[i], a.n())}));
    }
    requirements(clear, pp.between);
  }
  return pp;
}

}  // namespace marsyn::planning
