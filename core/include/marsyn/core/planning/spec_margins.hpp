#pragma once
// The global specification's requirements, once: which ones there are (each agent against each
// obstacle, each pair of agents, each formation pair), their names, and their signed margins
// (>= 0: met) at workspace points that may each move within a box around them. The eps-robust
// check passes each agent's WorkspaceMargin (how far its point moves inside the eps-box of its
// state); the verifier and the loader's start check pass none, which is the real specification
// (paper eq. 2 and 3). "The robust plan implies the real spec" therefore rests on one formula
// per requirement, with the margin box as its only difference.
//
// The same requirements on boxes of points, as sound lower bounds with rounding included (period
// enclosures, the continuous nominal), are box_margins.hpp's: a point evaluator reports exact
// depths of violations, a box evaluator only proves the requirement.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "marsyn/core/planning/geometry.hpp"
#include "marsyn/core/planning/margins.hpp"
#include "marsyn/core/planning/mission.hpp"
#include "marsyn/problem.hpp"

namespace marsyn::planning {

// The names of the specification's requirements, one spelling for the planning constraints, the
// robust check, the verifier and the certifier: AssemblyOptions::extra is keyed by them, so they must agree.
std::string obstacle_name(const Problem& problem, int obstacle, const AgentSpec& agent);
std::string collision_name(const AgentSpec& a, const AgentSpec& b);
std::string formation_name(const AgentSpec& a, const AgentSpec& b);
std::string state_bound_name(const AgentSpec& agent, int coordinate);

struct Requirement {
  enum Kind { Obstacle, Collision, Formation } kind;
  int a = 0;      // the body slot (obstacle), the first body slot (collision), the first agent (formation)
  int b = 0;      // the obstacle's index (obstacle), the second body slot (collision), agent (formation)
  int index = 0;  // the formation pair's index in problem.formation (formation only)

  std::string name(const Problem& problem) const;  // "obstacle wall vs drone1", "collision a vs b", ...
};

// Every workspace requirement of the problem once, always in this order: obstacles agent by
// agent, then pairs i < j (when pairwise collision is on), then the formation pairs.
// Obstacles and collisions are of body slots (Problem::body_count: each agent's first body, then
// the further ones), two bodies of one agent never a pair.
template <class Visit>
void for_each_requirement(const Problem& problem, Visit&& visit) {
  const int n = problem.body_count();
  for (int i = 0; i < n; ++i)
    for (int o = 0; o < static_cast<int>(problem.obstacles.size()); ++o) visit(Requirement{Requirement::Obstacle, i, o});
  if (problem.pairwise_collision)
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        if (problem.body_agent(i) != problem.body_agent(j)) visit(Requirement{Requirement::Collision, i, j});
  for (int q = 0; q < static_cast<int>(problem.formation.size()); ++q)
    visit(Requirement{Requirement::Formation, problem.formation[q].i, problem.formation[q].j, q});
}

// The requirements that bind at one moment: the staged obstacles only inside their windows.
template <class Visit>
void for_each_requirement(const Problem& problem, const ObstacleWindows& windows, Moment when, Visit&& visit) {
  for_each_requirement(problem, [&](const Requirement& q) {
    if (q.kind != Requirement::Obstacle || windows.binds(problem.body_agent(q.a), q.b, when)) visit(q);
  });
}


// d(O grown by the box (m.x, m.y, m.z), p) - delta in the problem's norm, signed (negative
// inside), O the obstacle's prism (its polygon where z is unbounded): >= 0 iff every point of
// p's box keeps delta from O (for convex O, exactly).
double obstacle_margin(const Obstacle& obstacle, const Point& p, const WorkspaceMargin& m, double delta, Norm norm);
// The polygon alone (z unbounded).
double obstacle_margin(const Polygon& obstacle, const Eigen::Vector2d& p, const WorkspaceMargin& m, double delta,
                       Norm norm);

// The smallest ||p' - q'|| - delta over p' in p's box and q' in q's box (inf-norm exact; 2-norm:
// the boxes' circumscribed balls).
double collision_margin(const Point& p, const WorkspaceMargin& mp, const Point& q, const WorkspaceMargin& mq,
                        double delta, Norm norm);

// (mu - slack) - | |p - q|_2 - lambda |, slack the two boxes' circumscribed radii: >= 0 keeps
// every pair of points of the boxes within lambda +- mu.
double formation_margin(const Point& p, const WorkspaceMargin& mp, const Point& q, const WorkspaceMargin& mq,
                        double lambda, double mu);

// One requirement at the bodies' points p (by body slot: the agents' first bodies in problem
// order, then the further ones; body_points below); m: their margin boxes, or nullptr for the
// real specification.
double requirement_margin(const Problem& problem, const Requirement& r, const std::vector<Point>& p,
                          const std::vector<WorkspaceMargin>* m = nullptr);

// p (resized to problem.body_count()): every body's workspace point at the product state x.
template <class S>
void body_points(const Problem& problem, const std::vector<int>& state_offsets, const S* x, std::vector<Point>& p) {
  p.resize(static_cast<std::size_t>(problem.body_count()));
  for (int s = 0; s < problem.body_count(); ++s) {
    const AgentSpec& b = problem.body_spec(s);
    workspace_point3(*b.dynamics, b.workspace, x + state_offsets[static_cast<std::size_t>(problem.body_agent(s))],
                     p[static_cast<std::size_t>(s)].data());
  }
}

// min(v - box.lo[c], box.hi[c] - v): how far coordinate c of a state keeps inside a box (goal,
// state bounds; shrink the box by eps for the robust version).
inline double inside_margin(const Box& box, int c, double v) { return std::min(v - box.lo[c], box.hi[c] - v); }

}  // namespace marsyn::planning
