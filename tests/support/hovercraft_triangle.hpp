#pragma once
// Three hovercraft (double integrators in x and y, written as equations) keeping a triangle
// formation with tolerance mu 0.35 on their way across a room: two tubes of 0.25 in position can
// change a pair's distance by 0.71 > mu. `eps_line` is added to `defaults` ("" leaves eps auto).
// Written to a temporary folder as <name>.yaml; returns its path.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

namespace marsyn::test {

inline std::string hovercraft_triangle(const std::string& name, const std::string& eps_line) {
  const std::string path = testing::TempDir() + "/" + name + ".yaml";
  std::ofstream(path) << "tau: 0.2\nhorizon: 60\ndelta: 0.2\n"
                         "defaults:\n"
                         "  dynamics: {states: [x, y, vx, vy], inputs: [ax, ay], field: {x: vx, y: vy, vx: ax, vy: ay}}\n"
                         "  state_bounds: {lo: [-1, -3, -1, -1], hi: [12, 3, 1, 1]}\n"
                         "  input_bounds: {lo: [-0.5, -0.5], hi: [0.5, 0.5]}\n"
                         "  disturbance: [0, 0, 0.02, 0.02]\n"
                         "  workspace: {position: [0, 1]}\n"
                      << eps_line
                      << "formation: {mu: 0.35, offsets: {h1: [0, 0], h2: [1, 0], h3: [0.5, 0.866]}}\n"
                         "agents:\n"
                         "  - {name: h1, x0: [0, 0, 0, 0], goal: {center: [10, 0, 0, 0], radius: [0.5, 0.5, 0.3, 0.3]}}\n"
                         "  - {name: h2, x0: [1, 0, 0, 0], goal: {center: [11, 0, 0, 0], radius: [0.5, 0.5, 0.3, 0.3]}}\n"
                         "  - {name: h3, x0: [0.5, 0.866, 0, 0], goal: {center: [10.5, 0.866, 0, 0], radius: [0.5, 0.5, 0.3, 0.3]}}\n";
  return path;
}

}  // namespace marsyn::test
