// Problem layout (agents, groups, constraint rows), the initial guess and rollouts.
#include "solver.hpp"

#include <algorithm>
#include <cmath>

#include "marsyn/planner_support/product_model.hpp"
#include "marsyn/sampled_map.hpp"
#include "rk4.hpp"

namespace marsyn::altro::detail {

void Solver::layout() {
  const auto& ag = prob_.agents;
  const ProductLayout at(prob_);
  for (std::size_t i = 0; i < ag.size(); ++i)
    agents_.push_back({ag[i].dynamics.get(), at.state[i], at.input[i], ag[i].n(), ag[i].m(), 0,
                       field_reads(*ag[i].dynamics)});
  n_ = at.state_dim();
  m_ = at.input_dim();
  const bool exact = opt_.coupling == "exact" || (opt_.coupling == "auto" && n_ <= opt_.exact_max_states);
  const int N = static_cast<int>(agents_.size());
  for (int i = 0; i < N; ++i) {
    if (exact && i > 0) {
      agents_[i].group = 0;
      groups_[0].n += agents_[i].n;
      groups_[0].m += agents_[i].m;
      groups_[0].last = i + 1;
      continue;
    }
    agents_[i].group = static_cast<int>(groups_.size());
    groups_.push_back({agents_[i].xo, agents_[i].uo, agents_[i].n, agents_[i].m, i, i + 1});
  }
  xgroup_.resize(n_);
  xlocal_.resize(n_);
  for (const auto& a : agents_)
    for (int i = 0; i < a.n; ++i) {
      xgroup_[a.xo + i] = a.group;
      xlocal_[a.xo + i] = a.xo + i - groups_[a.group].xo;
    }
  agent_of_.resize(n_);
  for (int i = 0; i < static_cast<int>(agents_.size()); ++i)
    for (int c = 0; c < agents_[i].n; ++c) agent_of_[agents_[i].xo + c] = i;
  auto ref = [&](const Constraint* c) {
    ConstraintRef r{c, c->size(), 0, {}, {}, 0};
    std::vector<int> seen;
    for (int s : c->support()) {
      r.group_of.push_back(xgroup_[s]);
      r.local.push_back(xlocal_[s]);
      if (std::find(seen.begin(), seen.end(), xgroup_[s]) == seen.end()) seen.push_back(xgroup_[s]);
    }
    r.groups_touched = static_cast<int>(seen.size());
    return r;
  };
  points_ = pp_.between.empty() ? 0 : std::max(0, pp_.between_points);
  // The rollout's substep states are then interior_points' numbers bit for bit: flow_points
  // steps substep by substep when there is one point per substep, and one midpoint's partial
  // step tau / 2 in substeps / 2 substeps has the substep tau / substeps exactly. (Other
  // splits agree only up to rounding: the points are integrated again.)
  kept_points_ = points_ > 0 && (points_ + 1 == prob_.rk4_substeps || (points_ == 1 && prob_.rk4_substeps % 2 == 0));
  kept_mid_jacobians_ = points_ == 1 && prob_.rk4_substeps % 2 == 0;
  if (points_ > 0)
    for (const auto& c : pp_.between) {
      ConstraintRef r = ref(c.get());
      r.lam_offset = between_rows_;
      between_rows_ += r.rows;
      between_.push_back(std::move(r));
    }
  for (const auto& c : pp_.constraints) {
    ConstraintRef r = ref(c.get());
    auto& list = c->stage() == ConstraintStage::Terminal ? terminal_ : stage_;
    int& rows = c->stage() == ConstraintStage::Terminal ? terminal_rows_ : stage_rows_;
    r.lam_offset = rows;
    rows += r.rows;
    list.push_back(std::move(r));
  }
  auto screen = [&](const std::vector<ConstraintRef>& refs) {
    std::vector<const Constraint*> cs;
    for (const auto& r : refs) cs.push_back(r.c);
    return std::make_unique<planner_support::ProximityScreen>(prob_, cs, opt_.broad_phase);
  };
  screen_ = screen(stage_);
  screen_b_ = screen(between_);
}

void Solver::step_agent(const AgentBlock& a, const Vec& x, const Vec& u, Vec& out, Vec* z) const {
  // Agent-sized models keep their last field evaluation (KeptField: the same states); a larger
  // one takes the generic step.
  KeptField field(*a.dyn, u.data() + a.uo, a.reads);
  auto step = [&](const double* from, double* to, int steps) {
    if (a.n <= kMaxDual) rk4_step_kept(field, a.n, from, prob_.tau, prob_.rk4_substeps, to, steps);
    else rk4_step<double>(*a.dyn, from, u.data() + a.uo, nullptr, prob_.tau, prob_.rk4_substeps, to, steps);
  };
  if (!z || !kept_points_) {
    step(x.data() + a.xo, out.data() + a.xo, -1);
    return;
  }
  // The period in points_ + 1 runs of `per` substeps each: rk4_step's arithmetic (each run
  // starts from the state the last one ended in), the states between the runs kept.
  const int per = prob_.rk4_substeps / (points_ + 1);
  double stack[kMaxDual * 16];
  std::vector<double> heap;
  double* buf = points_ * a.n <= kMaxDual * 16 ? stack : (heap.resize(static_cast<size_t>(points_) * a.n), heap.data());
  const double* from = x.data() + a.xo;
  for (int j = 0; j < points_; ++j) {
    step(from, buf + j * a.n, per);
    from = buf + j * a.n;
  }
  step(from, out.data() + a.xo, per);
  for (int j = 0; j < points_; ++j)
    for (int c = 0; c < a.n; ++c) (*z)[static_cast<long>(j) * n_ + a.xo + c] = buf[j * a.n + c];
}

void Solver::initial_guess() {
  goal_centre_ = planner_support::goal_centre(pp_);
  q_stage_ = Vec::Constant(n_, opt_.q_track);
  if (!opt_.q_state.empty()) q_stage_ = q_stage_.cwiseProduct(Eigen::Map<const Vec>(opt_.q_state.data(), n_));
  uniform_q_ = opt_.q_state.empty();
  for (const auto& w : pp_.waypoints)  // a route to follow weighs more than a straight line
    if (w.x.size() == n_ && w.follow > 1.0)
      for (int c = 0; c < n_; ++c)
        if (std::isfinite(w.x[c])) q_stage_[c] = std::max(q_stage_[c], w.follow * opt_.q_track), uniform_q_ = false;
  reference(opt_.bend);
  bend_ = opt_.bend;
  // Where the references of a team still meet (agents crossing one region at one time, as in
  // a swap), bend them all further: all to the same side, they form a roundabout. Each
  // candidate is scored by how deep the references cut into the pair requirements (the sum of
  // squared positive rows); the least bend that removes 99% of the first one's cut is kept, else
  // the shallowest cut. A reference free of cuts stays as it was. (A bend beyond what it takes
  // costs iterations: on the 50-agent swap 1.5 x the iterations at 4 x the bend against 3 x.)
  const bool pairs = std::any_of(stage_.begin(), stage_.end(),
                                 [](const ConstraintRef& r) { return std::isfinite(r.c->pair_reach()); });
  // Only under block coupling: one group sees every pair's conflict and resolves it in a few
  // iterations (multi_drone took two solves from 4 x its bend instead of one from its own), while
  // one group per agent resolves a crowd like a Jacobi iteration.
  if (opt_.bend_search && opt_.bend > 0 && groups_.size() >= 3 && pairs) {
    const double first = reference_conflict();
    double best = first, best_bend = opt_.bend;
    for (double f : {1.5, 2.0, 3.0, 4.0}) {
      if (best <= 0.01 * first) break;
      reference(f * opt_.bend);
      const double c = reference_conflict();
      if (c < best) best = c, best_bend = f * opt_.bend;
    }
    reference(best_bend);
    bend_ = best_bend;
  }
  U_.assign(T_, Vec::Zero(m_));
  if (pp_.warm_start && static_cast<int>(pp_.warm_start->u.size()) >= T_) {
    for (int k = 0; k < T_; ++k) U_[k] = pp_.warm_start->u[k];
  } else {
    for (int k = 0; k < T_; ++k)
      for (int j = 0; j < m_; ++j)
        U_[k][j] = std::clamp(0.0, pp_.input_bounds.lo[j], pp_.input_bounds.hi[j]);
  }
  rollout_nominal();
}

void Solver::reference(double bend) {
  ref_.assign(T_ + 1, Vec(n_));
  for (int k = 0; k <= T_; ++k) {
    const double s = static_cast<double>(k) / T_;
    ref_[k] = pp_.x0 + s * (goal_centre_ - pp_.x0);
  }
  // Mission stages: the reference runs through each stage's region centre at its visit knots
  // (PlanningProblem::waypoints), straight between them, in the coordinates the stages fix.
  // knots[c]: the knots where coordinate c is pinned (0 and T included); empty: a straight line.
  std::vector<std::vector<int>> knots(n_);
  for (int c = 0; c < n_; ++c) {
    std::vector<std::pair<int, double>> at{{0, pp_.x0[c]}};
    for (const auto& w : pp_.waypoints)
      if (w.x.size() == n_ && std::isfinite(w.x[c]) && w.step > at.back().first && w.step < T_) at.push_back({w.step, w.x[c]});
    if (at.size() == 1) continue;
    at.push_back({T_, goal_centre_[c]});
    for (std::size_t s = 0; s + 1 < at.size(); ++s) {
      knots[c].push_back(at[s].first);
      const auto [k0, v0] = at[s];
      const auto [k1, v1] = at[s + 1];
      for (int k = k0; k <= k1; ++k) ref_[k][c] = v0 + (v1 - v0) * (k - k0) / static_cast<double>(k1 - k0);
    }
    knots[c].push_back(T_);
  }
  // Straight lines of several agents may cross at one point at one time, a guess with no
  // feasible symmetric neighbour: bend each agent's reference sideways, by a slightly different
  // amount per agent (through waypoints: each leg between them).
  const int N = static_cast<int>(agents_.size());
  for (int i = 0; i < N; ++i) {
    const auto& ws = prob_.agents[i].workspace;
    if (!ws.linear() || ws.index[0] < 0 || ws.index[1] < 0) continue;
    const int ix = agents_[i].xo + ws.index[0], iy = agents_[i].xo + ws.index[1];
    std::vector<int> legs = knots[ix];
    legs.insert(legs.end(), knots[iy].begin(), knots[iy].end());
    std::sort(legs.begin(), legs.end());
    legs.erase(std::unique(legs.begin(), legs.end()), legs.end());
    if (legs.empty()) legs = {0, T_};
    const std::vector<Vec> line = ref_;
    for (std::size_t s = 0; s + 1 < legs.size(); ++s) {
      const int k0 = legs[s], k1 = legs[s + 1];
      // One leg (no waypoints): the goal centre itself, the arithmetic of the plain straight line.
      const Eigen::Vector2d dir = legs.size() == 2 ? Eigen::Vector2d(goal_centre_[ix] - pp_.x0[ix], goal_centre_[iy] - pp_.x0[iy])
                                                   : Eigen::Vector2d(line[k1][ix] - line[k0][ix], line[k1][iy] - line[k0][iy]);
      const double len = dir.norm();
      if (len < 1e-9) continue;
      const Eigen::Vector2d perp(-dir.y() / len, dir.x() / len);
      const double amp = bend * len * (1.0 + 0.2 * i / std::max(1, N - 1));
      for (int k = k0; k <= k1; ++k) {
        const double b = amp * std::sin(M_PI * (k - k0) / (k1 - k0));
        ref_[k][ix] += b * perp.x();
        ref_[k][iy] += b * perp.y();
      }
    }
  }
}

double Solver::reference_conflict() const {
  double sum = 0.0;
  std::vector<double>& g = scratch_;
  for (int k = 1; k <= T_; ++k) {
    screen_->near(ref_[k].data(), near_);
    for (int c : near_) {
      const auto& r = stage_[c];
      if (!std::isfinite(r.c->pair_reach())) continue;
      if (static_cast<int>(g.size()) < r.rows) g.resize(r.rows);
      r.c->evaluate(ref_[k].data(), g.data(), nullptr);
      for (int j = 0; j < r.rows; ++j) sum += g[j] > 0 ? g[j] * g[j] : 0.0;
    }
  }
  return sum;
}

void Solver::rollout_nominal() {
  X_.assign(T_ + 1, Vec(n_));
  X_[0] = pp_.x0;
  Z_.assign(kept_points_ ? T_ : 0, Vec(static_cast<long>(points_) * n_));
  for (int k = 0; k < T_; ++k)
    for (const auto& a : agents_) step_agent(a, X_[k], U_[k], X_[k + 1], kept_points_ ? &Z_[k] : nullptr);
}

}  // namespace marsyn::altro::detail
