#pragma once
// Goals that leave no room for the tubes: the eps-robust plan must end inside the goal shrunk by
// eps, with every obstacle (and every other agent, at its own shrunk goal) at least delta plus
// both workspace margins away. When no point of a shrunk goal keeps that distance, the plan fails
// at every horizon; a longer horizon is wasted and only a narrower tube (or another goal) helps.
// The diagnosis is exact for linear workspace maps (the distances are convex in the workspace
// point, so their largest value over a goal box is at one of its corners); agents with a
// nonlinear footprint are left out.
#include <string>
#include <vector>

#include "marsyn/problem.hpp"

namespace marsyn::planning {

struct CrowdedGoal {
  std::string agent;
  std::string other;    // "obstacle <name>", or the other agent's name
  double room = 0.0;    // the best robust margin any point of the shrunk goal(s) reaches: about 0 or below
  double eps_factor = 0.0;  // the factor on eps (both agents', every coordinate) that gives room 0; 0: none does
};

// Every crowded goal, least room first (at most `limit`; `total`, when given, receives the count).
std::vector<CrowdedGoal> crowded_goals(const Problem& problem, std::size_t limit = 8, std::size_t* total = nullptr);

// "a's goal leaves no room from obstacle wall: at its best the eps-robust plan ends 1e-08 short
// of delta and the tube's margin (at every horizon); eps x 0.99 or less (or a goal further away) would".
std::string describe(const CrowdedGoal& c, const Problem& problem);

// The smallest CrowdedGoal::eps_factor (any eps x f with f below it leaves every goal room), or 1.
double goal_eps_factor(const Problem& problem);

}  // namespace marsyn::planning
