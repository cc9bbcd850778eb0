#pragma once
// A one-unicycle problem for CLI tests: `top` holds the top-level lines after the horizon
// (tracker, plugin_paths, ...), `agent` the agent's name and `extra` more lines of its block.
#include <string>

namespace marsyn::test {

inline std::string one_unicycle(const std::string& top, const std::string& agent, const std::string& extra = "") {
  return "name: " + agent + "-alone\ntau: 0.1\nhorizon: 20\n" + top + R"(
agents:
  - name: )" + agent + R"(
    dynamics: unicycle
    x0: [0, 2, 0]
    goal: {center: [5, 2, 0], radius: [0.3, 0.3, 0.4]}
    state_bounds: {lo: [-1, -1, -2], hi: [11, 11, 3]}
    input_bounds: {lo: [-2, -2], hi: [2, 2]}
    disturbance: [0, 0.02, 0.02]
    eps: [0.2, 0.2, 0.24]
)" + extra;
}

}  // namespace marsyn::test
