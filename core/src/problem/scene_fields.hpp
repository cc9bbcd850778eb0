#pragma once
// The shared scene of the problem file: obstacles, formation, the collision plugin, and the
// real specification checked at the start states.
#include <cstddef>
#include <vector>

#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/problem.hpp"
#include "yaml_reader.hpp"

namespace marsyn::loader {

using yaml::Field;

// Each agent's workspace point at x0 keeps delta from every obstacle and every other agent.
void check_start_geometry(const Problem& pb, const std::vector<Field>& x0_fields);
// dim: the problem's workspace dimension (2 or 3), read from the agents before the obstacles.
Obstacle read_obstacle(const Field& f, std::size_t index, int dim);
// At least 3 vertices [[x, y], ...] of a convex polygon with area, returned counter-clockwise.
std::vector<Eigen::Vector2d> read_convex_polygon(const Field& p);
void read_formation(const Field& f, Problem& pb);
void read_collision(const Field& f, LoadedProblem& out);

}  // namespace marsyn::loader
