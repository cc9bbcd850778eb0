// A workspace `position` may name the states (as `marsyn plugins` and the equations list them)
// instead of giving their indices; both read the same.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "marsyn/core/problem/problem_loader.hpp"

namespace {

std::string with_position(const std::string& position, const std::string& tag) {
  std::ifstream in(std::string(MARSYN_SOURCE_DIR) + "/examples/multi_drone.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  const std::string from = "workspace: {position: [0, 1]}";
  s.replace(s.find(from), from.size(), "workspace: {position: " + position + "}");
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
