#pragma once
// Periodic coordinates in a problem (docs/problem-format.md "Periodic coordinates"): `any` in
// goals and in a periodic coordinate's bounds, and the branch of the lift each arc is kept on.
#include <string>
#include <vector>

#include "marsyn/problem.hpp"
#include "yaml_reader.hpp"

namespace marsyn::loader {

// A box like read_box whose entries may be `any` where `any_allowed` says so (an `any` entry
// comes back as NaN on both sides, resolved by lift_periodic). `what_any` says where `any` is
// allowed, for the message at an entry where it is not.
Box read_box_any(const yaml::Field& f, int n, const std::string& why, const std::vector<bool>& any_allowed,
                 const std::string& what_any);

// Where bounds may say `any`: "only in a periodic coordinate (... theta)", or that the model has none.
std::string bounds_any_rule(const Dynamics& dyn);

// Turns the agent's `any` entries and arcs into intervals of the lift (the angle as a real
// number, where the method works): a periodic coordinate's `any` bounds become x0 +- kFreeTurns
// turns, an arc of bounds narrower than a turn the branch holding x0; a goal's `any` becomes the
// state bounds, a periodic goal arc narrower than a turn the branch nearest x0 that fits inside
// the bounds (the shorter way round). Wider arcs are kept as written: they bound the lift.
inline constexpr double kFreeTurns = 2.0;
void lift_periodic(AgentSpec& a);
// The same for another box of the agent's state (a stage's region), after lift_periodic.
void lift_box(Box& box, const AgentSpec& a);

// The periodic coordinates' tubes must be narrower than half a turn either way, so that a
// measured angle lies on exactly one branch within the tube (the controllers unwrap by it).
void check_periodic_eps(const AgentSpec& a, const yaml::Field& epsf);

}  // namespace marsyn::loader

namespace marsyn::loader {

// The coordinate an agent travels along (its heading): a periodic coordinate i such that the
// velocity of its workspace point in the plane is parallel to (cos x_i, sin x_i) at sampled
// states and inputs (a unicycle's and a bicycle's theta); -1 when there is none.
int travel_heading(const AgentSpec& a);

// For agents that travel along a heading: the goal's (and stage boxes') arcs on the branch the
// way there winds to, not the one nearest x0: the heading is carried along the polyline from x0
// through the stages' regions to the goal (each leg around the obstacles, shortest_route), each
// leg turning the shorter way. A patrol round an island that returns to its start heading keeps
// the goal a turn on. Only a branch inside the bounds is taken. Extra bodies follow their owner.
void branch_by_route(Problem& pb);

}  // namespace marsyn::loader
