#include "periodic_fields.hpp"

#include <cmath>
#include <limits>
#include <random>

#include "marsyn/core/planning/routes.hpp"
#include "marsyn/core/planning/workspace_gaps.hpp"
#include "marsyn/core/problem/agent_checks.hpp"
#include "marsyn/number_text.hpp"
#include "marsyn/periodic.hpp"

namespace marsyn::loader {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool says_any(const yaml::Field& e) { return e.is_scalar() && e.text() == "any"; }

Eigen::VectorXd entries(const yaml::Field& f, int n, const std::string& why, const std::vector<bool>& any_allowed,
                        const std::string& what_any) {
  if (!f.present()) f.fail("missing value: expected a list of numbers");
  if (!f.is_sequence()) f.fail("expected a list of numbers like [1, 2, 3]");
  if (static_cast<int>(f.size()) != n)
    f.fail("expected " + std::to_string(n) + " numbers (" + why + "), got " + std::to_string(f.size()));
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) {
    const yaml::Field e = f[static_cast<std::size_t>(i)];
    if (says_any(e)) {
      if (!any_allowed[static_cast<std::size_t>(i)]) e.fail("expected a number; 'any' is allowed " + what_any);
      v[i] = kNaN;
    } else {
      v[i] = e.real();
    }
  }
  return v;
}

}  // namespace

Box read_box_any(const yaml::Field& f, int n, const std::string& why, const std::vector<bool>& any_allowed,
                 const std::string& what_any) {
  f.expect_map();
  Box b;
  if (f.child("center").present() || f.child("radius").present()) {
    f.allow_only({"center", "radius"});
    const Eigen::VectorXd c = entries(f.required("center"), n, why, any_allowed, what_any);
    const Eigen::VectorXd r = entries(f.required("radius"), n, why, any_allowed, what_any);
    for (int i = 0; i < n; ++i) {
      if (std::isnan(r[i]) != std::isnan(c[i]) && std::isnan(c[i]))
        f.child("center")[static_cast<std::size_t>(i)].fail("a centre 'any' needs the radius 'any' too");
      if (!std::isnan(r[i]) && !(r[i] >= 0))
        f.child("radius")[static_cast<std::size_t>(i)].fail("expected a non-negative number, got " + number_text(r[i]));
    }
    b = {c - r, c + r};  // NaN where the radius says any
    for (int i = 0; i < n; ++i)
      if (std::isnan(r[i])) b.lo[i] = b.hi[i] = kNaN;
  } else {
    f.allow_only({"lo", "hi"});
    b = {entries(f.required("lo"), n, why, any_allowed, what_any), entries(f.required("hi"), n, why, any_allowed, what_any)};
    for (int i = 0; i < n; ++i) {
      if (std::isnan(b.lo[i]) != std::isnan(b.hi[i]))
        (std::isnan(b.lo[i]) ? f.child("hi") : f.child("lo"))[static_cast<std::size_t>(i)].fail(
            "'any' on one side only; write 'any' for both lo and hi");
      if (b.lo[i] > b.hi[i])
        f.child("lo")[static_cast<std::size_t>(i)].fail("lower bound " + number_text(b.lo[i]) + " exceeds upper bound " +
                                                        number_text(b.hi[i]));
    }
  }
  return b;
}

std::string bounds_any_rule(const Dynamics& dyn) {
  const std::vector<bool> periodic = dyn.periodic();
  const auto names = dyn.state_names();
  std::string list;
  for (std::size_t i = 0; i < periodic.size() && i < names.size(); ++i)
    if (periodic[i]) list += (list.empty() ? "" : ", ") + names[i];
  if (list.empty() && dyn.type().rfind("equations:", 0) == 0)
    return "only in the bounds of a periodic coordinate, and these equations declare none (`periodic: [theta]` beside `states` declares one)";
  return list.empty() ? "only in the bounds of a periodic coordinate, and the dynamics '" + dyn.type() + "' has none"
                      : "only in the bounds of a periodic coordinate (the dynamics '" + dyn.type() + "' turns freely in " + list + ")";
}

void lift_periodic(AgentSpec& a) {
  for (int i = 0; i < a.n(); ++i) {
    const bool p = periodic_coordinate(a, i);
    double &lo = a.state_bounds.lo[i], &hi = a.state_bounds.hi[i];
    if (p && std::isnan(lo)) {
      lo = a.x0[i] - kFreeTurns * kTurn;
      hi = a.x0[i] + kFreeTurns * kTurn;
    } else if (p && hi - lo < kTurn && !(lo <= a.x0[i] && a.x0[i] <= hi)) {
      // The arc as written may be another branch than x0's: the one holding x0, when one does.
      const double k = std::floor((a.x0[i] - lo) / kTurn);
      if (lo + k * kTurn <= a.x0[i] && a.x0[i] <= hi + k * kTurn) lo += k * kTurn, hi += k * kTurn;
    }
  }
  lift_box(a.goal, a);
}

namespace {

// Whole turns k that bring [lo, hi] + 2 pi k nearest `target` among those inside [blo, bhi] (an
// exact tie goes counter-clockwise, the larger angle); the nearest overall when none fits.
double nearest_turns(double lo, double hi, double target, double blo, double bhi) {
  const double mid = 0.5 * (lo + hi);
  const double k0 = std::nearbyint((target - mid) / kTurn);
  // Past 2^52 turns k0 +- 1 is k0 itself (an angle of 1e49 in a file): no branch to choose.
  if (!(std::abs(k0) < 0x1p52)) return 0.0;
  double best = k0, best_off = std::numeric_limits<double>::infinity();
  bool found = false;
  for (int j = -3; j <= 3; ++j) {
    const double k = k0 + j;
    if (!(blo <= lo + k * kTurn && hi + k * kTurn <= bhi)) continue;
    const double off = std::abs(mid + k * kTurn - target);
    if (!found || off < best_off - 1e-9 * (1 + off) || (std::abs(off - best_off) <= 1e-9 * (1 + off) && k > best)) {
      best = k;
      best_off = off;
      found = true;
    }
  }
  return best;
}

}  // namespace

void lift_box(Box& box, const AgentSpec& a) {
  for (int i = 0; i < a.n(); ++i) {
    const bool p = periodic_coordinate(a, i);
    const double lo = a.state_bounds.lo[i], hi = a.state_bounds.hi[i];
    double &glo = box.lo[i], &ghi = box.hi[i];
    if (std::isnan(glo)) {
      glo = lo;
      ghi = hi;
    } else if (p && ghi - glo < kTurn) {
      // The branch nearest x0 (the shorter way round) among those inside the bounds; the nearest
      // overall when none fits (the goal's check then says so).
      const double k = nearest_turns(glo, ghi, a.x0[i], lo, hi);
      glo += k * kTurn;
      ghi += k * kTurn;
    }
  }
}

void check_periodic_eps(const AgentSpec& a, const yaml::Field& epsf) {
  const auto names = a.dynamics->state_names();
  for (int i = 0; i < a.n() && i < a.tube.eps.size(); ++i)
    if (angle_tube_too_wide(a, i)) {
      const yaml::Field at = epsf.is_sequence() ? epsf[static_cast<std::size_t>(i)] : epsf;
      at.fail("eps in '" + names[static_cast<std::size_t>(i)] + "', a periodic coordinate (an angle), is " + number_text(a.tube.eps[i]) +
              "; it must be below pi/2 = 1.571 so that a measured angle lies on one branch of the tube");
    }
}

int travel_heading(const AgentSpec& a) {
  if (!a.workspace.linear() || a.workspace.index.size() < 2 || a.workspace.index[0] < 0 || a.workspace.index[1] < 0) return -1;
  const std::vector<bool> periodic = a.dynamics->periodic();
  const int n = a.n(), m = a.m(), ix = a.workspace.index[0], iy = a.workspace.index[1];
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> x(static_cast<std::size_t>(n)), u(static_cast<std::size_t>(m)), dx(static_cast<std::size_t>(n));
  for (int h = 0; h < n && h < static_cast<int>(periodic.size()); ++h) {
    if (!periodic[static_cast<std::size_t>(h)]) continue;
    bool parallel = true, moves = false;
    for (int s = 0; s < 64 && parallel; ++s) {
      for (int i = 0; i < n; ++i) {
        const double lo = a.state_bounds.lo[i], hi = a.state_bounds.hi[i];
        x[static_cast<std::size_t>(i)] = i == h ? -M_PI + 2 * M_PI * unit(rng) : lo + (hi - lo) * unit(rng);
      }
      for (int j = 0; j < m; ++j) u[static_cast<std::size_t>(j)] = a.input_bounds.lo[j] + (a.input_bounds.hi[j] - a.input_bounds.lo[j]) * unit(rng);
      a.dynamics->field(x.data(), u.data(), dx.data());
      const double vx = dx[static_cast<std::size_t>(ix)], vy = dx[static_cast<std::size_t>(iy)], th = x[static_cast<std::size_t>(h)];
      const double speed = std::hypot(vx, vy);
      if (!std::isfinite(speed)) return -1;
      moves = moves || speed > 1e-6;
      parallel = std::abs(vx * std::sin(th) - vy * std::cos(th)) <= 1e-9 * (1 + speed);
    }
    if (parallel && moves) return h;
  }
  return -1;
}

void branch_by_route(Problem& pb) {
  std::vector<planning::Polygon> polygons;
  double vertices = 0;
  for (const auto& o : pb.obstacles)
    if (!o.staged) polygons.push_back(o.vertices), vertices += static_cast<double>(o.vertices.size());
  // A blocked leg's visibility graph costs about vertices^2 x polygons segment tests: past a
  // budget over all the legs (hundreds of robots among hundreds of pillars), legs go straight.
  double legs = 0;
  for (const auto& a : pb.agents) legs += 1.0 + static_cast<double>(a.stages.size());
  const bool around = vertices * vertices * static_cast<double>(polygons.size()) * legs <= 2e8;
  for (std::size_t ai = 0; ai < pb.agents.size(); ++ai) {
    AgentSpec& a = pb.agents[ai];
    const int h = travel_heading(a);
    if (h < 0) continue;
    // Nothing to choose where no arc is narrower than a turn.
    bool arcs = a.goal.hi[h] - a.goal.lo[h] < kTurn;
    for (const auto& st : a.stages) arcs = arcs || (!st.is_polygon() && st.box.hi[h] - st.box.lo[h] < kTurn);
    if (!arcs) continue;
    // The way's points in the workspace (the obstacles' frame): start, stages, goal.
    const std::vector<Eigen::Vector2d> way = planning::way_points(a);
    if (way.size() != a.stages.size() + 2) continue;
    double heading = a.x0[h];
    Eigen::Vector2d at = way.front();
    // Carries the heading along the leg to `to`, around the obstacles, each segment the shorter way.
    auto travel = [&](const Eigen::Vector2d& to) {
      bool found = false;
      std::vector<Eigen::Vector2d> corners;
      if (around) {
        try {
          corners = planning::shortest_route(polygons, at, to, &found);
        } catch (const std::exception&) {
          corners.clear();
        }
      }
      if (!found) corners.clear();
      corners.push_back(to);
      for (const auto& c : corners) {
        const Eigen::Vector2d d = c - at;
        if (d.norm() > 1e-9) heading += angle_difference(std::atan2(d.y(), d.x()), heading);
        at = c;
      }
    };
    // An arc narrower than a turn onto the branch nearest the heading carried there, when that
    // branch lies inside the bounds; true when the box is such an arc.
    auto rebranch = [&](Box& b) {
      if (!(b.hi[h] - b.lo[h] < kTurn)) return false;
      const double k = nearest_turns(b.lo[h], b.hi[h], heading, a.state_bounds.lo[h], a.state_bounds.hi[h]);
      if (a.state_bounds.lo[h] <= b.lo[h] + k * kTurn && b.hi[h] + k * kTurn <= a.state_bounds.hi[h]) {
        b.lo[h] += k * kTurn;
        b.hi[h] += k * kTurn;
      }
      return true;
    };
    for (std::size_t si = 0; si < a.stages.size(); ++si) {
      travel(way[si + 1]);
      // The robot leaves the stage with the heading the stage holds it to.
      MissionStage& st = a.stages[si];
      if (!st.is_polygon() && rebranch(st.box)) heading = 0.5 * (st.box.lo[h] + st.box.hi[h]);
    }
    travel(way.back());
    rebranch(a.goal);
    for (auto& e : pb.extra_bodies)
      if (e.agent == static_cast<int>(ai)) {
        e.spec.goal = a.goal;
        e.spec.stages = {};
      }
  }
}

}  // namespace marsyn::loader
