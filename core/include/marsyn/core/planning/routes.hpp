#pragma once
// Routes around the obstacles (issue 22, "routes, not only local descent"): when the local
// planner keeps pushing agents into a gap they cannot pass, a shortest path per agent in the
// workspace, around the obstacles grown by what the eps-robust plan keeps from them, gives the
// planner another homotopy class to start from. The route enters the planning problem as
// waypoints (PlanningProblem::waypoints: a hint for the initial guess, never a requirement).
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "marsyn/core/planning/geometry.hpp"
#include "marsyn/core/planning/mission.hpp"
#include "marsyn/planner.hpp"
#include "marsyn/problem.hpp"

namespace marsyn::planning {

// The shortest polyline from `from` to `to` that keeps out of the interior of every polygon
// (convex, counter-clockwise): a visibility graph over the polygons' vertices, searched with
// Dijkstra. The corners between the two ends, in order; empty when the straight segment is
// free, and when no route exists or an end lies inside a polygon (`found` false then).
std::vector<Eigen::Vector2d> shortest_route(const std::vector<Polygon>& polygons, const Eigen::Vector2d& from,
                                            const Eigen::Vector2d& to, bool* found = nullptr);

// An obstacle of a 3-D workspace: a convex polygon in x-y (counter-clockwise) times [z_lo, z_hi]
// (either end may be infinite).
struct Prism {
  Polygon base;
  double z_lo, z_hi;
};

// A short polyline from `from` to `to` inside the box [lo, hi] that keeps out of the interior of
// every prism. Shortest paths in space bend on the obstacles' edges, not only at their vertices,
// so a visibility graph over vertices can miss them (a window in a wall of boxes has no vertex
// of its own): the search runs over a lattice whose planes are the prisms' bounding planes, the
// ends' coordinates and a uniform refinement, with every lattice edge checked exactly against
// the prisms, and the lattice path is then shortened by skipping to the farthest visible
// corner. Exact for boxes' openings (their faces are lattice planes), approximate (but always
// obstacle-free) around slanted polygons. The corners between the ends; empty when the straight
// segment is free, and when no route exists in the lattice or an end is inside a prism
// (`found` false then).
std::vector<Eigen::Vector3d> route_in_space(const std::vector<Prism>& prisms, const Eigen::Vector3d& lo,
                                            const Eigen::Vector3d& hi, const Eigen::Vector3d& from,
                                            const Eigen::Vector3d& to, bool* found = nullptr);

// Another homotopy class: a thin wall from inside the first obstacle the straight segment
// from-to crosses, out past everything (`reach`) on the side where the route `corners` passes
// it (beside it at every height; or above or below it, a sheet across the way, when the route
// goes over or under). A route that avoids the wall as well passes that obstacle on another
// side. None when the straight segment crosses nothing or the route does not pass it.
std::optional<Prism> other_side_barrier(const std::vector<Prism>& prisms, const Eigen::Vector3d& from,
                                        const Eigen::Vector3d& to, const std::vector<Eigen::Vector3d>& corners,
                                        double reach);

// Waypoints for every agent with a linear workspace whose straight way crosses an obstacle grown
// by delta + its workspace margin (+ 10%, so the route does not graze what the plan must clear):
// the route's corners at knots in proportion to the distance along it. An agent's way is its
// start to its goal centre, or, with mission stages, its legs through the stages' regions at their
// visit knots in `visits` (the initial schedule at this horizon when `visits` is none for it):
// start to the first region's point, each region's to the next's after its dwell, the last to
// the goal; each leg routed around the obstacles that bind the agent on it (staged ones only on
// the legs that name them), its corners at knots between the leg's ends. Empty when no leg is
// blocked. In a 3-D workspace the route is taken in space (route_in_space, inside the agent's
// position bounds less its margin) over the grown prisms, which grow in z as well.
// Agents listed in `other_side` get another homotopy class where one exists inside their
// position bounds: each leg's route passes the first obstacle on its way on another side
// (other_side_barrier); the shortest route otherwise.
std::vector<Waypoint> route_waypoints(const Problem& problem, int horizon, const MissionSchedule& visits = {},
                                      const std::vector<int>& other_side = {});

}  // namespace marsyn::planning
