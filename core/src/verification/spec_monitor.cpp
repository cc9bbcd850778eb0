#include "marsyn/core/verification/spec_monitor.hpp"

#include <algorithm>
#include <cmath>

namespace marsyn {

SpecMonitor::SpecMonitor(const Problem& problem) : problem_(problem) {
  const ProductLayout layout(problem);
  offset_.assign(layout.state.begin(), layout.state.end() - 1);
  for (const auto& o : problem.obstacles) {
    Eigen::Vector4d b(1e300, 1e300, -1e300, -1e300);
    for (const auto& v : o.vertices) {
      b[0] = std::min(b[0], v.x());
      b[1] = std::min(b[1], v.y());
      b[2] = std::max(b[2], v.x());
      b[3] = std::max(b[3], v.y());
    }
    bbox_.push_back(b);
  }
}

bool SpecMonitor::accumulate(const Eigen::VectorXd& x, StepMargins& running) const {
  const StepMargins before = running;
  const int n = static_cast<int>(problem_.agents.size());
  const bool inf = problem_.delta_norm == Norm::Inf;
  thread_local std::vector<Eigen::Vector2d> pts;
  pts.resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) pts[i] = point(i, x);
  for (int i = 0; i < n; ++i)
    for (std::size_t o = 0; o < problem_.obstacles.size(); ++o) {
      // Outside its bounding box, a point is at least as far from the obstacle as from the box.
      const Eigen::Vector4d& b = bbox_[o];
      const double gx = std::max(b[0] - pts[i].x(), pts[i].x() - b[2]), gy = std::max(b[1] - pts[i].y(), pts[i].y() - b[3]);
      if (gx > 0 || gy > 0) {
        const double px = std::max(gx, 0.0), py = std::max(gy, 0.0);
        const double lb = (inf ? std::max(px, py) : std::sqrt(px * px + py * py)) - problem_.delta;
        if (lb >= running.obstacle) continue;
      }
      const auto& ob = problem_.obstacles[o];
      const double d = (inf ? signed_distance_inf(ob.vertices, pts[i]) : signed_distance_two(ob.vertices, pts[i])) -
                       problem_.delta;
      running.obstacle = std::min(running.obstacle, d);
    }
  if (problem_.pairwise_collision)
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        const Eigen::Vector2d d = pts[i] - pts[j];
        running.collision = std::min(running.collision, (inf ? d.lpNorm<Eigen::Infinity>() : d.norm()) - problem_.delta);
      }
  for (const auto& f : problem_.formation)
    running.formation = std::min(running.formation, f.mu - std::abs((pts[f.i] - pts[f.j]).norm() - f.lambda));
  return running.obstacle < before.obstacle || running.collision < before.collision ||
         running.formation < before.formation;
}

Eigen::Vector2d SpecMonitor::point(int agent, const Eigen::VectorXd& x) const {
  const AgentSpec& a = problem_.agents[agent];
  double p[2];
  workspace_point<double>(*a.dynamics, a.workspace, x.data() + offset_[agent], p);
  return {p[0], p[1]};
}

StepMargins SpecMonitor::step(const Eigen::VectorXd& x, std::string* worst) const {
  StepMargins m;
  const int n = static_cast<int>(problem_.agents.size());
  std::vector<Eigen::Vector2d> pts(n);
  for (int i = 0; i < n; ++i) pts[i] = point(i, x);
  const bool inf = problem_.delta_norm == Norm::Inf;
  // The name of the smallest margin is built once, at the end: this runs at every integration
  // substep of every verification run.
  double best = 1e300;
  int kind = -1, wa = -1, wb = -1;
  auto note = [&](double v, int k, int a, int b) {
    if (worst && v < best) {
      best = v;
      kind = k;
      wa = a;
      wb = b;
    }
  };
  for (int i = 0; i < n; ++i)
    for (std::size_t o = 0; o < problem_.obstacles.size(); ++o) {
      const auto& ob = problem_.obstacles[o];
      const double d = (inf ? signed_distance_inf(ob.vertices, pts[i]) : signed_distance_two(ob.vertices, pts[i])) -
                       problem_.delta;
      m.obstacle = std::min(m.obstacle, d);
      note(d, 0, static_cast<int>(o), i);
    }
  if (problem_.pairwise_collision)
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        const Eigen::Vector2d d = pts[i] - pts[j];
        const double v = (inf ? d.lpNorm<Eigen::Infinity>() : d.norm()) - problem_.delta;
        m.collision = std::min(m.collision, v);
        note(v, 1, i, j);
      }
  for (std::size_t q = 0; q < problem_.formation.size(); ++q) {
    const auto& f = problem_.formation[q];
    const double v = f.mu - std::abs((pts[f.i] - pts[f.j]).norm() - f.lambda);
    m.formation = std::min(m.formation, v);
    note(v, 2, f.i, f.j);
  }
  if (worst && kind >= 0) {
    const auto& ag = problem_.agents;
    if (kind == 0) *worst = "obstacle " + problem_.obstacles[static_cast<size_t>(wa)].name + " vs " + ag[wb].name;
    else if (kind == 1) *worst = "collision " + ag[wa].name + " vs " + ag[wb].name;
    else *worst = "formation " + ag[wa].name + " - " + ag[wb].name;
  }
  return m;
}

SpecEvaluation SpecMonitor::evaluate(const std::vector<Eigen::VectorXd>& states, bool keep_per_step) const {
  SpecEvaluation ev;
  for (std::size_t k = 0; k < states.size(); ++k) {
    std::string what;
    const StepMargins m = step(states[k], &what);
    if (keep_per_step) ev.per_step.push_back(m);
    if (m.min() < ev.min_margin) {
      ev.min_margin = m.min();
      ev.worst = what + " at step " + std::to_string(k);
    }
  }
  if (!states.empty()) {
    const Eigen::VectorXd& x = states.back();
    for (std::size_t i = 0; i < problem_.agents.size(); ++i) {
      const AgentSpec& a = problem_.agents[i];
      for (int c = 0; c < a.n(); ++c) {
        const double v = std::min(x[offset_[i] + c] - a.goal.lo[c], a.goal.hi[c] - x[offset_[i] + c]);
        if (v < ev.goal_margin) ev.goal_margin = v;
        if (v < ev.min_margin) {
          ev.min_margin = v;
          ev.worst = "goal of " + a.name + " (" + a.dynamics->state_names()[c] + ") at the final step";
        }
      }
    }
  }
  ev.satisfied = ev.min_margin >= 0;
  return ev;
}

}  // namespace marsyn
