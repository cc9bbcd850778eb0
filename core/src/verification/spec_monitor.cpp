#include "marsyn/core/verification/spec_monitor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "marsyn/core/planning/spec_margins.hpp"

namespace marsyn {

SpecMonitor::SpecMonitor(const Problem& problem, int horizon) : problem_(problem) {
  const ProductLayout layout(problem);
  offset_.assign(layout.state.begin(), layout.state.end() - 1);
  if (horizon > 0) {
    visits_ = planning::stage_visits(problem, horizon);
    windows_ = planning::ObstacleWindows(problem, horizon);
  }
  for (const planning::StageVisit& v : visits_) {
    const MissionStage& st = problem.agents[v.agent].stages[v.stage];
    stage_edges_.emplace_back(st.polygon);
    double scale = 0;
    for (const Eigen::Vector2d& q : st.polygon) scale = std::max(scale, q.cwiseAbs().maxCoeff());
    stage_scale_.push_back(scale);
  }
}

bool SpecMonitor::stage_clears(int v, const planning::Point& p, double value) const {
  const planning::PolygonEdges& e = stage_edges_[static_cast<size_t>(v)];
  if (e.a.empty()) return false;
  // Depth inside edge k: -normal_k . (p - a_k) (stage_margin's cross(e, p - a) / |e|). A repeated
  // vertex's NaN normal is passed over by min (the loader refuses those anyway).
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < e.a.size(); ++k) d = std::min(d, e.normal[k].x() * (e.a[k].x() - p.x()) + e.normal[k].y() * (e.a[k].y() - p.y()));
  const double slack = 1e-9 * (1.0 + std::abs(value) + stage_scale_[static_cast<size_t>(v)] + std::max(std::abs(p.x()), std::abs(p.y())));
  return d > value + slack;
}

double SpecMonitor::stage_depth(const planning::StageVisit& v, const Eigen::VectorXd& x) const {
  const AgentSpec& a = problem_.agents[v.agent];
  const double* xi = x.data() + offset_[v.agent];
  planning::Point p;
  workspace_point3<double>(*a.dynamics, a.workspace, xi, p.data());
  return stage_depth(v, xi, p);
}

double SpecMonitor::stage_depth(const planning::StageVisit& v, const double* xi, const planning::Point& p) const {
  return planning::stage_margin(problem_.agents[v.agent].stages[v.stage], xi, xi, p.data(), p.data());
}

void SpecMonitor::add_stages(int k, const Eigen::VectorXd& x, SpecEvaluation& ev) const {
  for (const auto& v : visits_) {
    if (k < v.step || k > v.step + v.dwell) continue;
    const double m = stage_depth(v, x);
    if (m < ev.min_margin) {
      ev.min_margin = m;
      ev.worst = v.name + " at step " + std::to_string(k);
    }
  }
}

double SpecMonitor::stage_between(int k, const Eigen::VectorXd& x, std::string* name) const {
  double out = 1e300;
  for (const auto& v : visits_) {
    if (!v.dwells_over(k)) continue;
    const double m = stage_depth(v, x);
    if (m < out) {
      out = m;
      if (name) *name = v.name;
    }
  }
  return out;
}

namespace {

double& part(StepMargins& m, planning::Requirement::Kind kind) {
  switch (kind) {
    case planning::Requirement::Obstacle: return m.obstacle;
    case planning::Requirement::Collision: return m.collision;
    case planning::Requirement::Formation: break;
  }
  return m.formation;
}

}  // namespace

void SpecMonitor::points(const Eigen::VectorXd& x, std::vector<planning::Point>& p) const {
  planning::body_points(problem_, offset_, x.data(), p);
}

StepMargins SpecMonitor::step(const Eigen::VectorXd& x, std::string* worst, planning::Moment when) const {
  StepMargins m;
  std::vector<planning::Point> pts;
  points(x, pts);
  // The name of the smallest margin is built once, at the end: this runs at every integration
  // substep of every verification run.
  double best = 1e300;
  planning::Requirement at{planning::Requirement::Obstacle, -1, -1};
  static const planning::ObstacleWindows always;
  planning::for_each_requirement(problem_, when.k >= 0 ? windows_ : always, when, [&](const planning::Requirement& q) {
    const double v = planning::requirement_margin(problem_, q, pts);
    double& slot = part(m, q.kind);
    slot = std::min(slot, v);
    if (worst && v < best) {
      best = v;
      at = q;
    }
  });
  if (worst && at.a >= 0) *worst = at.name(problem_);
  return m;
}

SpecEvaluation SpecMonitor::evaluate(const std::vector<Eigen::VectorXd>& states, bool keep_per_step) const {
  SpecEvaluation ev;
  // The staged obstacles' windows and the stages' knots at these states' horizon.
  const SpecMonitor at(problem_, static_cast<int>(states.size()) - 1);
  for (std::size_t k = 0; k < states.size(); ++k) {
    std::string what;
    const StepMargins m = at.step(states[k], &what, {static_cast<int>(k), false});
    if (keep_per_step) ev.per_step.push_back(m);
    if (m.min() < ev.min_margin) {
      ev.min_margin = m.min();
      ev.worst = what + " at step " + std::to_string(k);
    }
  }
  if (!states.empty()) add_goal(states.back(), ev);
  if (states.size() > 1 && at.has_stages()) {
    for (std::size_t k = 0; k < states.size(); ++k) at.add_stages(static_cast<int>(k), states[k], ev);
  }
  ev.satisfied = ev.min_margin >= 0;
  return ev;
}

void SpecMonitor::add_goal(const Eigen::VectorXd& x, SpecEvaluation& ev) const {
  for (std::size_t i = 0; i < problem_.agents.size(); ++i) {
    const AgentSpec& a = problem_.agents[i];
    for (int c = 0; c < a.n(); ++c) {
      const double v = planning::inside_margin(a.goal, c, x[offset_[i] + c]);
      if (v < ev.goal_margin) ev.goal_margin = v;
      if (v < ev.min_margin) {
        ev.min_margin = v;
        ev.worst = "goal of " + a.name + " (" + a.dynamics->state_names()[c] + ") at the final step";
      }
    }
  }
}

}  // namespace marsyn
