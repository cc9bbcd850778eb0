// The answer nlopt, ipopt and ompl give before building anything (invalid_input.hpp).
#include <gtest/gtest.h>

#include "marsyn/planner_support/invalid_input.hpp"
#include "test_problems.hpp"

using namespace marsyn;

TEST(InvalidInput, NoProblemOrNoPositiveHorizonIsRefused) {
  const Problem problem = testproblems::pendulum_problem(10);
  PlanningProblem pp;
  pp.horizon = 10;
  const auto no_problem = planner_support::invalid_input(pp);
  ASSERT_TRUE(no_problem.has_value());
  EXPECT_EQ(no_problem->status, PlannerStatus::InvalidInput);
  EXPECT_EQ(no_problem->message, "no problem or a non-positive horizon");
  pp.problem = &problem;
  EXPECT_FALSE(planner_support::invalid_input(pp).has_value());
  pp.horizon = 0;
  EXPECT_TRUE(planner_support::invalid_input(pp).has_value());
}
