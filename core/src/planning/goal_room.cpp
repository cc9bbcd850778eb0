#include "marsyn/core/planning/goal_room.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "marsyn/core/planning/margins.hpp"
#include "marsyn/core/planning/mission.hpp"
#include "marsyn/core/planning/spec_margins.hpp"
#include "marsyn/number_text.hpp"

namespace marsyn::planning {

namespace {

// A room this small is no room: the planner cannot end a plan exactly on the boundary, and the
// corner arithmetic rounds a room of exactly 0 to either side.
constexpr double kNoRoom = 1e-9;

// One agent's shrunk goal in the workspace at a factor on eps: the corners of its image box and
// the tube's margin there. Empty when the agent has a footprint, its goal is unbounded in a
// workspace coordinate, or the goal shrinks to nothing.
struct GoalImage {
  std::vector<Point> corners;  // 4 in the plane (z = 0), 8 in space
  WorkspaceMargin margin;
};

std::optional<GoalImage> goal_image(const AgentSpec& a, double f) {
  if (!a.workspace.linear() || a.goal.dim() != a.n() || a.tube.eps.size() != a.n()) return std::nullopt;
  const int dim = a.workspace.dim();
  std::array<double, kMaxWorkspaceDim> lo{}, hi{};
  for (int c = 0; c < dim; ++c) {
    const int at = a.workspace.index[c];
    const double off = a.workspace.offset[c];
    if (at < 0) {
      lo[c] = hi[c] = off;
      continue;
    }
    lo[c] = a.goal.lo[at] + f * a.tube.eps[at] + off;
    hi[c] = a.goal.hi[at] - f * a.tube.eps[at] + off;
    if (!std::isfinite(lo[c]) || !std::isfinite(hi[c])) return std::nullopt;
    // A goal exactly 2 eps wide shrinks to a point, which rounding may turn inside out.
    if (lo[c] > hi[c] && lo[c] - hi[c] <= 1e-12 * std::max(1.0, std::abs(lo[c]))) lo[c] = hi[c] = 0.5 * (lo[c] + hi[c]);
    if (lo[c] > hi[c]) return std::nullopt;
  }
  GoalImage g;
  for (int corner = 0; corner < (1 << dim); ++corner) {
    Point p = Point::Zero();
    for (int c = 0; c < dim; ++c) p[c] = (corner >> c) & 1 ? hi[c] : lo[c];
    g.corners.push_back(p);
  }
  AgentSpec scaled = a;
  scaled.tube.eps = f * a.tube.eps;
  Eigen::VectorXd centre = a.x0;
  for (int i = 0; i < a.n(); ++i)
    if (std::isfinite(a.goal.lo[i]) && std::isfinite(a.goal.hi[i])) centre[i] = 0.5 * (a.goal.lo[i] + a.goal.hi[i]);
  g.margin = margin_at(scaled, centre);  // the linear map's margin does not depend on the state
  return g;
}

// The best robust margin over the shrunk goal(s) at a factor on eps (the margins are convex in the
// workspace points, so the best is at corners); +inf when there is nothing to judge.
double obstacle_room(const Problem& pb, const AgentSpec& a, const Obstacle& obstacle, double f) {
  const auto g = goal_image(a, f);
  if (!g) return std::numeric_limits<double>::infinity();
  double best = -std::numeric_limits<double>::infinity();
  for (const auto& p : g->corners) best = std::max(best, obstacle_margin(obstacle, p, g->margin, pb.obstacle_delta() + a.radius, pb.delta_norm));
  return best;
}

double pair_room(const Problem& pb, const AgentSpec& a, const AgentSpec& b, double f) {
  const auto ga = goal_image(a, f), gb = goal_image(b, f);
  if (!ga || !gb) return std::numeric_limits<double>::infinity();
  double best = -std::numeric_limits<double>::infinity();
  for (const auto& p : ga->corners)
    for (const auto& q : gb->corners)
      best = std::max(best, collision_margin(p, ga->margin, q, gb->margin, pb.delta + a.radius + b.radius, pb.delta_norm));
  return best;
}

// The factor in [0, 1] where a room that grows as eps shrinks reaches 0 (bisection; the room is
// monotone: a smaller eps widens the shrunk goal and narrows the margins). 0 when eps -> 0 does
// not give room either.
template <class Room>
double zero_room_factor(const Room& room) {
  if (room(0.0) < kNoRoom) return 0.0;
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < 40; ++it) {
    const double mid = 0.5 * (lo + hi);
    (room(mid) >= kNoRoom ? lo : hi) = mid;
  }
  return lo;
}

std::vector<CrowdedGoal> all_crowded_goals(const Problem& pb) {
  std::vector<CrowdedGoal> out;
  const ObstacleWindows windows(pb, pb.horizon);
  const Moment end{pb.horizon, false};
  for (std::size_t i = 0; i < pb.agents.size(); ++i) {
    const AgentSpec& a = pb.agents[i];
    for (std::size_t o = 0; o < pb.obstacles.size(); ++o) {
      if (!windows.binds(static_cast<int>(i), static_cast<int>(o), end)) continue;
      const Obstacle& obstacle = pb.obstacles[o];
      const double room = obstacle_room(pb, a, obstacle, 1.0);
      if (!(room < kNoRoom)) continue;
      out.push_back({a.name, "obstacle " + pb.obstacles[o].name, room,
                     zero_room_factor([&](double f) { return obstacle_room(pb, a, obstacle, f); })});
    }
  }
  if (pb.pairwise_collision)
    for (std::size_t i = 0; i < pb.agents.size(); ++i)
      for (std::size_t j = i + 1; j < pb.agents.size(); ++j) {
        const AgentSpec &a = pb.agents[i], &b = pb.agents[j];
        const double room = pair_room(pb, a, b, 1.0);
        if (!(room < kNoRoom)) continue;
        out.push_back({a.name, b.name, room, zero_room_factor([&](double f) { return pair_room(pb, a, b, f); })});
      }
  std::sort(out.begin(), out.end(), [](const CrowdedGoal& x, const CrowdedGoal& y) { return x.room < y.room; });
  return out;
}

}  // namespace

std::vector<CrowdedGoal> crowded_goals(const Problem& problem, std::size_t limit, std::size_t* total) {
  auto out = all_crowded_goals(problem);
  if (total) *total = out.size();
  if (out.size() > limit) out.resize(limit);
  return out;
}

double goal_eps_factor(const Problem& problem) {
  double f = 1.0;
  for (const auto& c : all_crowded_goals(problem)) f = std::min(f, c.eps_factor);
  return f;
}

namespace {
bool radii(const Problem& problem, const CrowdedGoal& c) {
  for (const auto& a : problem.agents)
    if ((a.name == c.agent || a.name == c.other) && a.radius > 0) return true;
  return false;
}
}  // namespace

std::string describe(const CrowdedGoal& c, const Problem& problem) {
  std::ostringstream os;
  os.precision(kMessageDigits);
  const bool obstacle = c.other.rfind("obstacle ", 0) == 0;
  os << (obstacle ? c.agent + "'s goal leaves no room for its tube beside " + c.other
                  : c.agent + "'s and " + c.other + "'s goals leave no room for their tubes between them")
     << ": ending inside the goal" << (obstacle ? "" : "s") << " shrunk by eps, the robust margin (delta "
     << (obstacle ? problem.obstacle_delta() : problem.delta) << (radii(problem, c) ? " and the bodies' radii" : "")
     << (problem.delta_norm == Norm::Inf ? " in the inf-norm" : " Euclidean") << " and the tube"
     << (obstacle ? "'s" : "s'") << " margin) is at most " << (std::abs(c.room) < kNoRoom ? 0.0 : c.room)
     << ": no horizon can help; ";
  if (c.eps_factor > 0)
    os << "eps x " << std::floor(c.eps_factor * 100) / 100 << " or less (or a larger goal) would leave room";
  else
    os << "only a larger goal " << (obstacle ? "or one further from the obstacle" : "or goals further apart") << " would leave room";
  return os.str();
}

}  // namespace marsyn::planning
