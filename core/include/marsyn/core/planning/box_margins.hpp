#pragma once
// The safety part of the specification evaluated on boxes instead of points: sound lower bounds,
// rounding included, of how far a box of workspace points (or states) keeps each requirement.
// The continuous-time check of a plan (robust_check) and the certification of the trackers'
// period enclosures (certification.hpp) both read the spec through these functions, so "the
// enclosures pass" and "the real spec holds" rest on one evaluator (docs/soundness.md, §10).
#include <vector>

#include "marsyn/box.hpp"
#include "marsyn/interval.hpp"
#include "marsyn/core/planning/geometry.hpp"
#include "marsyn/core/planning/spec_margins.hpp"
#include "marsyn/problem.hpp"

namespace marsyn::planning {

// A lower bound of dist(B, P) - delta in the given norm, for the workspace box B (2 coordinates)
// and the convex polygon P: >= 0 implies every point of B keeps delta from P. Negative when B
// meets P grown by delta (its magnitude is then only indicative).
double box_obstacle_margin(const Box& workspace, const Polygon& obstacle, double delta, Norm norm);
// The same against the obstacle's prism (polygon x [z_lo, z_hi]) for a 3-D workspace box; a
// 2-D box, or an obstacle unbounded in z, is judged by the polygon alone (the distance to the
// prism is never below the distance in x-y).
double box_obstacle_margin(const Box& workspace, const Obstacle& obstacle, double delta, Norm norm);

// Agent (or body) a's workspace box over a box of its states, outward rounded: a linear map by one
// directed addition per coordinate, a footprint in interval arithmetic. D: the box's dimension;
// xb, pb: scratch. The second form sizes the box by a's map.
void workspace_box(const AgentSpec& a, int D, const Box& state, std::vector<Interval>& xb, std::vector<Interval>& pb,
                   Box& out);
Box workspace_box(const AgentSpec& a, const Box& state);

// A lower bound of dist(A, B) - delta between two workspace boxes (2 or 3 coordinates).
double box_pair_margin(const Box& a, const Box& b, double delta, Norm norm);

// A lower bound of min(|p - q|_2 - (lambda - mu), (lambda + mu) - |p - q|_2) over p in A, q in B.
double box_formation_margin(const Box& a, const Box& b, double lambda, double mu);

// One requirement (spec_margins.hpp) on the agents' workspace boxes ws (problem order).
double box_requirement_margin(const Problem& problem, const Requirement& r, const std::vector<Box>& ws);
// Body slot a's clearance to obstacles and the pair (a, b)'s, with their radii, rounded up: the
// certified margins subtract them rounded down.
double obstacle_clearance_up(const Problem& problem, int a);
double pair_clearance_up(const Problem& problem, int a, int b);

// min over coordinates of (box.lo - X.lo, X.hi - box.hi): >= 0 iff the box lies in X; with
// coord >= 0, that coordinate only.
double box_inside_margin(const Box& box, const Box& X, int coord = -1);

}  // namespace marsyn::planning
