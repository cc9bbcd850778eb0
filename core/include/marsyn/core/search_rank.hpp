#pragma once
// Which lever each failed agent gets (docs/search.md, "Each failed agent its own lever"). A
// round with several agents without a controller serves each with the lever its own failure
// calls for (a small miss its wider tube, an empty winning set its finer grid), merged into one
// round; the choice per agent follows the evidence's order (levers_for), except that a tracker's
// knob predicted to take longer than another tracker waits behind that tracker.
#include <string>
#include <vector>

#include "marsyn/core/search_levers.hpp"

namespace marsyn::search {

// A lever that can run for one agent: its proposal (made for that agent alone) and the
// predicted seconds to its controller.
struct Candidate {
  LeverChoice lever;
  Proposal proposal;
  double predicted_s = 0.0;
};

// The index of the candidate to take among `candidates` (each viable, in the evidence's order):
// the first, except that a tracker knob (Lever::TrackerLever) predicted slower than a fallback
// to another tracker among them is passed over. -1 when there are none.
int best_candidate(const std::vector<Candidate>& candidates);

// The failure of `failure.agents[w]` alone (its reason, miss and saturation), to choose its lever.
Failure agent_failure(const Failure& failure, std::size_t w);

// One proposal from several agents' own picks (each made for its agent alone, on the same team):
// each agent's spec, tracker choice and share of U from its pick, the changes in the order given.
// It re-plans when a pick does; it may keep the plan (recheck) only when every pick that
// re-plans only widened tubes. Team-wide settings (clearance, starting horizon) stay the team's.
Proposal merge(const std::vector<Proposal>& picks, const Team& team);

// The round's action as reported: the lever's name when every pick used the same one, else
// "<agent>: <lever>; ..." in the order given.
std::string merged_action(const std::vector<std::string>& names, const std::vector<std::string>& agents);

}  // namespace marsyn::search
