// A workspace `position` may name the states (as `marsyn plugins` and the equations list them)
// instead of giving their indices; both read the same.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "marsyn/core/problem/problem_loader.hpp"

namespace {

std::string with_position(const std::string& position, const std::string& tag, const std::string& line_break = "") {
  std::ifstream in(std::string(MARSYN_SOURCE_DIR) + "/examples/multi_drone.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  const std::string from = "workspace: {position: [0, 1]}";
  s.replace(s.find(from), from.size(), position.empty() ? line_break : "workspace: {position: " + position + "}");
  const std::string path = testing::TempDir() + "workspace_names_" + tag + ".yaml";
  std::ofstream(path) << s;
  return path;
}

}  // namespace

TEST(WorkspaceNames, StateNamesReadAsTheirIndices) {
  const auto by_index = marsyn::load_problem(with_position("[0, 1]", "index"));
  const auto by_name = marsyn::load_problem(with_position("[x, y]", "name"));
  const auto swapped = marsyn::load_problem(with_position("[y, 0]", "swapped"));
  for (std::size_t i = 0; i < by_name.problem.agents.size(); ++i) {
    EXPECT_EQ(by_name.problem.agents[i].workspace.index, by_index.problem.agents[i].workspace.index);
    EXPECT_EQ(swapped.problem.agents[i].workspace.index, (std::vector<int>{1, 0}));
  }
}

TEST(WorkspaceNames, AnUnknownNameIsALocatedError) {
  try {
    marsyn::load_problem(with_position("[x, heading]", "unknown"));
    ADD_FAILURE() << "a state the unicycle does not have was accepted";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("position[1]"), std::string::npos) << what;
    EXPECT_NE(what.find("the states x, y, theta"), std::string::npos) << what;
  }
}

// No workspace: a model with states named x and y is in the plane at (x, y), as a user of the
// unicycle expects; one without them is still told to give it.
TEST(WorkspaceNames, StatesNamedXAndYAreTheDefaultPosition) {
  const auto lp = marsyn::load_problem(with_position("", "default", "# workspace by default"));
  ASSERT_FALSE(lp.problem.agents.empty());
  EXPECT_EQ(lp.problem.workspace_dim, 2);
  for (const auto& a : lp.problem.agents) EXPECT_EQ(a.workspace.index, (std::vector<int>{0, 1}));
  const std::string path = testing::TempDir() + "workspace_no_xy.yaml";
  std::ofstream(path) << "name: no-xy\ntau: 0.1\nhorizon: 20\ndelta: 0.2\n"
                         "defaults:\n  dynamics: {states: [p, q], inputs: [a, b], field: {p: a, q: b}}\n"
                         "  state_bounds: {lo: [-5, -5], hi: [5, 5]}\n  input_bounds: {lo: [-1, -1], hi: [1, 1]}\n"
                         "  disturbance: [0.01, 0.01]\n  eps: [0.1, 0.1]\n"
                         "agents:\n  - {name: one, x0: [0, 0], goal: {center: [1, 0], radius: [0.3, 0.3]}}\n"
                         "  - {name: two, x0: [0, 2], goal: {center: [1, 2], radius: [0.3, 0.3]}}\n";
  try {
    marsyn::load_problem(path);
    ADD_FAILURE() << "a team of models without x and y states got a workspace";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("missing required field 'workspace'"), std::string::npos) << what;
    EXPECT_NE(what.find("no x and y to take by default"), std::string::npos) << what;
  }
}
