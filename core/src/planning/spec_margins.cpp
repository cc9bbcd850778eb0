#include "marsyn/core/planning/spec_margins.hpp"

#include <algorithm>
#include <cmath>

namespace marsyn::planning {

std::string obstacle_name(const Problem& pb, int o, const AgentSpec& a) {
  const std::string& n = pb.obstacles[static_cast<size_t>(o)].name;
  return "obstacle " + (n.empty() ? std::to_string(o) : n) + " vs " + a.name;
}
std::string collision_name(const AgentSpec& a, const AgentSpec& b) { return "collision " + a.name + " vs " + b.name; }
std::string formation_name(const AgentSpec& a, const AgentSpec& b) { return "formation " + a.name + " - " + b.name; }
std::string state_bound_name(const AgentSpec& a, int c) {
  const std::string coord = a.dynamics ? a.dynamics->state_names()[static_cast<size_t>(c)] : "x" + std::to_string(c);
  return "state bound " + coord + " of " + a.name;
}

std::string Requirement::name(const Problem& problem) const {
  const auto& ag = problem.agents;
  switch (kind) {
    case Obstacle: return obstacle_name(problem, b, problem.body_spec(a));
    case Collision: return collision_name(problem.body_spec(a), problem.body_spec(b));
    case Formation: break;
  }
  return formation_name(ag[static_cast<size_t>(a)], ag[static_cast<size_t>(b)]);
}

double obstacle_margin(const Polygon& obstacle, const Eigen::Vector2d& p, const WorkspaceMargin& m, double delta,
                       Norm norm) {
  // Every point of p + box(m) keeps delta iff p keeps delta from P + box(m) (Minkowski sums
  // commute); without a margin the polygon itself, saving the hull on the verifier's hot path.
  const bool grown = m.x != 0.0 || m.y != 0.0;
  const Polygon g = grown ? grow_by_box(obstacle, m.x, m.y) : Polygon{};
  const Polygon& P = grown ? g : obstacle;
  return (norm == Norm::Inf ? signed_distance_inf(P, p) : signed_distance_two(P, p)) - delta;
}

double obstacle_margin(const Obstacle& o, const Point& p, const WorkspaceMargin& m, double delta, Norm norm) {
  // A prism grown by a box is the grown polygon times the grown interval.
  const double s = obstacle_margin(o.vertices, Eigen::Vector2d(p.x(), p.y()), m, 0.0, norm);
  if (!o.z_bounded()) return s - delta;
  const double h = z_gap(p.z(), o.z_lo - m.z, o.z_hi + m.z);
  return prism_combine(s, h, norm == Norm::Inf) - delta;
}

double collision_margin(const Point& p, const WorkspaceMargin& mp, const Point& q, const WorkspaceMargin& mq,
                        double delta, Norm norm) {
  const Point d = p - q;
  // Inf-norm: the margin boxes add, and ||d'||_inf >= delta for every d' in d + box(m_p + m_q)
  // iff one coordinate clears its sum. Without z (the plane; a 3-D pair at one altitude without
  // z margins) the z term is left out: the plane's value bit for bit, and never above the 3-D one.
  if (norm == Norm::Inf) {
    const double xy = std::max(std::abs(d.x()) - (delta + mp.x + mq.x), std::abs(d.y()) - (delta + mp.y + mq.y));
    if (d.z() == 0.0 && mp.z == 0.0 && mq.z == 0.0) return xy;
    return std::max(xy, std::abs(d.z()) - (delta + mp.z + mq.z));
  }
  return distance2(d) - (delta + mp.two() + mq.two());
}

double formation_margin(const Point& p, const WorkspaceMargin& mp, const Point& q, const WorkspaceMargin& mq,
                        double lambda, double mu) {
  return (mu - (mp.two() + mq.two())) - std::abs(distance2(p - q) - lambda);
}

double requirement_margin(const Problem& problem, const Requirement& r, const std::vector<Point>& p,
                          const std::vector<WorkspaceMargin>* m) {
  static const WorkspaceMargin none;
  const auto box = [&](int i) -> const WorkspaceMargin& { return m ? (*m)[static_cast<size_t>(i)] : none; };
  const auto& pa = p[static_cast<size_t>(r.a)];
  switch (r.kind) {
    case Requirement::Obstacle:
      return obstacle_margin(problem.obstacles[static_cast<size_t>(r.b)], pa, box(r.a), problem.obstacle_clearance(r.a),
                             problem.delta_norm);
    case Requirement::Collision:
      return collision_margin(pa, box(r.a), p[static_cast<size_t>(r.b)], box(r.b), problem.pair_clearance(r.a, r.b),
                             problem.delta_norm);
    case Requirement::Formation: break;
  }
  const FormationPair& f = problem.formation[static_cast<size_t>(r.index)];
  return formation_margin(pa, box(r.a), p[static_cast<size_t>(r.b)], box(r.b), f.lambda, f.mu);
}

}  // namespace marsyn::planning
