#include "ompl_solver.hpp"

#include <algorithm>
#include <cmath>
#include <atomic>
#include <limits>
#include <mutex>
#include <random>
#include <sstream>

#include <ompl/base/goals/GoalSampleableRegion.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/control/PathControl.h>
#include <ompl/control/SpaceInformation.h>
#include <ompl/control/planners/kpiece/KPIECE1.h>
#include <ompl/control/planners/rrt/RRT.h>
#include <ompl/control/planners/sst/SST.h>
#include <ompl/control/spaces/RealVectorControlSpace.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include "marsyn/stopwatch.hpp"
#include "marsyn/planner_support/invalid_input.hpp"
#include "marsyn/planner_support/product_model.hpp"
#include "marsyn/number_text.hpp"

namespace marsyn::ompl_planner {

namespace ob = ompl::base;
namespace oc = ompl::control;

namespace {

using Vec = Eigen::VectorXd;

// OMPL samples uniformly inside the state bounds, so unbounded coordinates get a finite box
// around the start and the goal.
void finite_box(const planner_support::ProductModel& M, Vec& lo, Vec& hi) {
  const auto& pp = M.pp;
  lo = pp.state_bounds.lo;
  hi = pp.state_bounds.hi;
  for (int i = 0; i < M.n; ++i) {
    const double a = std::min(pp.x0[i], M.goal_centre[i]), b = std::max(pp.x0[i], M.goal_centre[i]);
    const double pad = 1.0 + (b - a);
    if (!std::isfinite(lo[i])) lo[i] = a - pad;
    if (!std::isfinite(hi[i])) hi[i] = b + pad;
  }
}

// knot >= 0: only the rows that apply there (a mission stage's rows at its visit knots).
bool rows_ok(const planner_support::RowSet& rows, const double* x, int knot = -1) {
  return rows.rows() == 0 || rows.worst(x, nullptr, knot) <= 0.0;
}

// The requirements between the samples, at the interior points of the period from x under u.
bool between_ok(const planner_support::ProductModel& M, const double* x, const double* u) {
  if (M.points == 0 || M.between.rows() == 0) return true;
  std::vector<double> z(M.n);
  for (int j = 1; j <= M.points; ++j) {
    M.interior(x, u, j, z.data());
    if (!rows_ok(M.between, z.data())) return false;
  }
  return true;
}

class GoalBox : public ob::GoalSampleableRegion {
 public:
  GoalBox(const ob::SpaceInformationPtr& si, const planner_support::ProductModel& M, Vec lo, Vec hi, double t_max)
      : ob::GoalSampleableRegion(si), M_(M), lo_(std::move(lo)), hi_(std::move(hi)), t_max_(t_max) {
    // OMPL accepts distances strictly below the threshold; distanceGoal is exactly 0 inside.
    setThreshold(std::numeric_limits<double>::min());
  }
  double distanceGoal(const ob::State* s) const override {
    const double* x = s->as<ob::RealVectorStateSpace::StateType>()->values;
    return std::max(0.0, M_.terminal.rows() ? M_.terminal.worst(x, nullptr) : 0.0);
  }
  void sampleGoal(ob::State* s) const override {
    double* x = s->as<ob::RealVectorStateSpace::StateType>()->values;
    for (int i = 0; i < M_.n; ++i) x[i] = rng_.uniformReal(lo_[i], hi_[i]);
    x[M_.n] = rng_.uniformReal(0.0, t_max_);
  }
  unsigned int maxSampleCount() const override { return 1u << 30; }
  bool isSatisfied(const ob::State* s, double* distance) const override {
    const bool in = ob::GoalRegion::isSatisfied(s, distance);
    if (in) reached_ = true;
    return in;
  }
  using ob::GoalRegion::isSatisfied;
  // A tree state has entered the goal: the planner holds an exact solution from then on (SST
  // publishes it only when solve() returns, so OMPL's own exact-solution condition never fires).
  bool reached() const { return reached_; }

 private:
  const planner_support::ProductModel& M_;
  Vec lo_, hi_;
  double t_max_;
  mutable ompl::RNG rng_;
  mutable std::atomic<bool> reached_{false};
};

// After the path reaches the goal, each further step takes, of the candidate controls that keep
// the state valid, the one landing deepest in the goal (least terminal-row violation, then
// nearest the goal centre scaled by the goal's size). Only x_T must be in the goal; the final
// measurement decides.
bool hold_in_goal(const planner_support::ProductModel& M, const Options& o, std::vector<Vec>& U, std::vector<Vec>& X,
                  std::string& why) {
  const auto& pp = M.pp;
  Vec scale = Vec::Ones(M.n);
  for (int i = 0; i < M.n; ++i) {
    const double w = pp.goal.hi[i] - pp.goal.lo[i];
    scale[i] = std::isfinite(w) && w > 0 ? 2.0 / w : 0.0;
  }
  std::mt19937 rng(12345);
  Vec next(M.n);
  while (static_cast<int>(U.size()) < M.T) {
    std::vector<Vec> cand{Vec::Zero(M.m), U.empty() ? Vec::Zero(M.m) : U.back()};
    for (int c = 0; c < o.hold_candidates; ++c) {
      Vec u(M.m);
      for (int j = 0; j < M.m; ++j)
        u[j] = std::uniform_real_distribution<double>(pp.input_bounds.lo[j], pp.input_bounds.hi[j])(rng);
      cand.push_back(u);
    }
    std::pair<double, double> best{INFINITY, INFINITY};
    Vec best_u, best_x;
    for (auto& u : cand) {
      for (int j = 0; j < M.m; ++j) u[j] = std::clamp(u[j], pp.input_bounds.lo[j], pp.input_bounds.hi[j]);
      M.step(X.back().data(), u.data(), next.data());
      if (!rows_ok(M.path, next.data(), static_cast<int>(U.size()) + 1) || !between_ok(M, X.back().data(), u.data()))
        continue;
      const double out = M.terminal.rows() ? std::max(0.0, M.terminal.worst(next.data(), nullptr)) : 0.0;
      const std::pair<double, double> s{out, (next - M.goal_centre).cwiseProduct(scale).squaredNorm()};
      if (s < best) best = s, best_u = u, best_x = next;
    }
    if (!std::isfinite(best.first)) {
      why = "no candidate control keeps the state valid at step " + std::to_string(U.size() + 1);
      return false;
    }
    U.push_back(best_u);
    X.push_back(best_x);
  }
  if (M.terminal.rows() && M.terminal.worst(X.back().data(), nullptr) > 0.0) {
    why = "the state could not be held until T: it leaves the goal";
    return false;
  }
  return true;
}

// The product system as OMPL's control problem: state (x, scaled elapsed time) in the sampling
// box, controls in U, propagation by whole steps, validity by the path rows.
oc::SpaceInformationPtr space_information(const planner_support::ProductModel& M, const PlanningProblem& pp,
                                          const Options& o, const Vec& lo, const Vec& hi) {
  const int n = M.n, m = M.m;
  const double t_max = M.T * M.tau;
  auto space = std::make_shared<ob::RealVectorStateSpace>(n + 1);
  ob::RealVectorBounds sb(n + 1);
  // The sampling box also holds x0, which may lie outside the shrunk bounds (OMPL refuses a
  // start outside the space); the shrunk bounds themselves are validity rows.
  for (int i = 0; i < n; ++i) {
    sb.setLow(i, std::min(lo[i], pp.x0[i]));
    sb.setHigh(i, std::max(hi[i], pp.x0[i]));
  }
  // Elapsed time, scaled: bounding it by T tau is what keeps every path within the horizon.
  sb.setLow(n, 0.0);
  sb.setHigh(n, o.time_weight * t_max + 1e-9);
  space->setBounds(sb);
  auto cspace = std::make_shared<oc::RealVectorControlSpace>(space, m);
  ob::RealVectorBounds cb(m);
  for (int j = 0; j < m; ++j) {
    cb.setLow(j, pp.input_bounds.lo[j]);
    cb.setHigh(j, pp.input_bounds.hi[j]);
  }
  cspace->setBounds(cb);
  auto si = std::make_shared<oc::SpaceInformation>(space, cspace);
  const double tau = M.tau, tw = o.time_weight;
  si->setStatePropagator([&M, tau, tw, n](const ob::State* s, const oc::Control* c, double duration, ob::State* out) {
    const double* x = s->as<ob::RealVectorStateSpace::StateType>()->values;
    const double* u = c->as<oc::RealVectorControlSpace::ControlType>()->values;
    double* y = out->as<ob::RealVectorStateSpace::StateType>()->values;
    const int steps = std::max(1, static_cast<int>(std::lround(duration / tau)));
    std::vector<double> a(x, x + n), b(n);
    bool between = true;
    for (int k = 0; k < steps; ++k) {
      between = between && between_ok(M, a.data(), u);
      M.step(a.data(), u, b.data());
      a.swap(b);
    }
    std::copy(a.begin(), a.end(), y);
    // A motion that breaks a requirement between its samples: a time past the space's bounds
    // makes the landing state invalid, so OMPL discards the motion (the checker sees states only).
    y[n] = between ? x[n] + tw * tau * steps : std::numeric_limits<double>::infinity();
  });
  si->setStateValidityChecker([&M, n, tau, tw, si_raw = si.get()](const ob::State* s) {
    const double* x = s->as<ob::RealVectorStateSpace::StateType>()->values;
    // Elapsed time 0 is the start alone (propagation adds time). x0 is fixed, so, as for the
    // other planners, nothing is required of it; OMPL would otherwise refuse the problem.
    if (x[n] == 0.0) return true;
    if (!si_raw->satisfiesBounds(s)) return false;
    // The knot of this state from its elapsed time (propagation adds whole steps).
    return rows_ok(M.path, x, static_cast<int>(std::lround(x[n] / (tw * tau))));
  });
  // Explicit: OMPL's defaults derive the step from the state space's extent (distance units).
  si->setPropagationStepSize(tau);
  si->setMinMaxControlDuration(1, o.max_control_steps);
  si->setup();
  return si;
}

ob::PlannerPtr make_planner(const oc::SpaceInformationPtr& si, const Options& o) {
  if (o.planner == "rrt") {
    auto p = std::make_shared<oc::RRT>(si);
    p->setGoalBias(o.goal_bias);
    return p;
  }
  if (o.planner == "kpiece1") {
    auto p = std::make_shared<oc::KPIECE1>(si);
    p->setGoalBias(o.goal_bias);
    return p;
  }
  auto p = std::make_shared<oc::SST>(si);
  p->setGoalBias(o.goal_bias);
  p->setSelectionRadius(o.selection_radius);
  p->setPruningRadius(o.pruning_radius);
  return p;
}

// What a solve that found no exact solution reports.
PlannerStatus failure_status(const ob::PlannerStatus& st) {
  switch (ob::PlannerStatus::StatusType(st)) {
    case ob::PlannerStatus::INVALID_START:
    case ob::PlannerStatus::INVALID_GOAL:
    case ob::PlannerStatus::UNRECOGNIZED_GOAL_TYPE: return PlannerStatus::InvalidInput;
    case ob::PlannerStatus::CRASH:
    case ob::PlannerStatus::ABORT: return PlannerStatus::Crash;
    default: return PlannerStatus::Timeout;  // time ran out (with or without an approximation)
  }
}

// The exact solution path as the plan: its controls step by step, then held in the goal until
// T; the message goes on in `msg`.
void plan_from_path(const planner_support::ProductModel& M, const Options& o, const oc::PathControl& path,
                    std::ostringstream& msg, PlanResult& res) {
  std::vector<Vec> U;
  for (size_t i = 0; i < path.getControlCount(); ++i) {
    const double* u = path.getControl(i)->as<oc::RealVectorControlSpace::ControlType>()->values;
    const int steps = std::max(1, static_cast<int>(std::lround(path.getControlDuration(i) / M.tau)));
    for (int k = 0; k < steps; ++k) U.push_back(Eigen::Map<const Vec>(u, M.m));
  }
  const int reached = static_cast<int>(U.size());
  std::vector<Vec> X = M.rollout(U);
  std::string why;
  if (reached > M.T) {
    res.status = PlannerStatus::ApproximateSolution;
    msg << "; the path needs " << reached << " steps, more than T = " << M.T;
    res.message = msg.str();
    return;
  }
  const bool held = hold_in_goal(M, o, U, X, why);
  res.plan.tau = M.tau;
  res.plan.u = U;
  res.plan.x = M.rollout(U);
  std::string worst;
  res.max_violation = held ? M.violation(res.plan.x, U, &worst) : INFINITY;
  for (const auto& u : U) res.cost += 0.5 * u.squaredNorm();
  msg << "; goal reached after " << reached << " of " << M.T << " steps";
  if (held && res.max_violation <= o.feasibility_tolerance) {
    res.status = PlannerStatus::ExactSolution;
  } else {
    res.status = PlannerStatus::ApproximateSolution;
    msg << "; " << (held ? "worst: " + worst : why);
    if (!held) {
      // The path is still returned, padded with zeros, for inspection (core's exact check decides).
      while (static_cast<int>(res.plan.u.size()) < M.T) res.plan.u.push_back(Vec::Zero(M.m));
      res.plan.x = M.rollout(res.plan.u);
    }
  }
  res.message = msg.str();
}

std::once_flag seed_once;

}  // namespace

PlanResult solve(const PlanningProblem& pp, const PlanOptions& run, const Options& o) {
  const Stopwatch clock;
  if (auto refused = planner_support::invalid_input(pp)) return *refused;
  PlanResult res;
  if (o.seed >= 0) std::call_once(seed_once, [&] { ompl::RNG::setSeed(static_cast<std::uint_fast32_t>(o.seed)); });
  ompl::msg::setLogLevel(ompl::msg::LOG_ERROR);
  planner_support::ProductModel M(pp);
  const int n = M.n;
  Vec lo, hi;
  finite_box(M, lo, hi);
  const oc::SpaceInformationPtr si = space_information(M, pp, o, lo, hi);

  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  ob::ScopedState<> start(si->getStateSpace());
  for (int i = 0; i < n; ++i) start[i] = pp.x0[i];
  start[n] = 0.0;
  pdef->addStartState(start);
  Vec glo(n), ghi(n);
  for (int i = 0; i < n; ++i) {
    glo[i] = std::isfinite(pp.goal.lo[i]) ? std::max(pp.goal.lo[i], lo[i]) : lo[i];
    ghi[i] = std::isfinite(pp.goal.hi[i]) ? std::min(pp.goal.hi[i], hi[i]) : hi[i];
  }
  auto goal = std::make_shared<GoalBox>(si, M, glo, ghi, o.time_weight * (M.T * M.tau));
  pdef->setGoal(goal);

  ob::PlannerPtr planner = make_planner(si, o);
  planner->setProblemDefinition(pdef);
  planner->setup();
  const double limit = std::min(o.time_limit_s, run.time_limit_s);
  // SST keeps refining after its first solution; the first exact one is all that is needed.
  auto ptc = ob::plannerOrTerminationCondition(ob::timedPlannerTerminationCondition(limit),
                                               ob::PlannerTerminationCondition([goal] { return goal->reached(); }));
  ob::PlannerStatus st;
  try {
    st = planner->solve(ptc);
  } catch (const std::exception& e) {
    res.status = PlannerStatus::Crash;
    res.message = std::string("OMPL threw: ") + e.what();
    return res;
  }
  ob::PlannerData data(si);
  planner->getPlannerData(data);
  res.iterations = static_cast<int>(data.numVertices());
  res.solve_time_s = clock.seconds();
  std::ostringstream msg;
  msg.precision(kMessageDigits);
  msg << o.planner << ": " << st.asString() << ", " << data.numVertices() << " tree vertices";
  const bool exact = st == ob::PlannerStatus::EXACT_SOLUTION && pdef->hasExactSolution() && !pdef->hasApproximateSolution();
  if (!exact) {
    res.status = failure_status(st);
    msg << "; no exact solution within " << limit << " s";
    if (pdef->hasApproximateSolution()) msg << " (nearest miss " << pdef->getSolutionDifference() << " from the goal)";
    res.message = msg.str();
    return res;
  }
  plan_from_path(M, o, *pdef->getSolutionPath()->as<oc::PathControl>(), msg, res);
  return res;
}

}  // namespace marsyn::ompl_planner
