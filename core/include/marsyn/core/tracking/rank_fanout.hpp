#pragma once
// The per-agent fan-out over the ranks of an MPI run (docs/mpi.md). Every rank calls it with the
// same problem and plan. An agent whose estimated work (TrackerAssessment::work_s) exceeds one
// rank's fair share (total / ranks) is tracked by all ranks together (its tracker splits its
// sweep through TrackOptions::collective), the heaviest first; the others are dealt to ranks
// largest first, each to the least loaded rank, and each rank tracks its own with its threads.
// Outcomes and controllers (as their file bytes) are then exchanged, so every rank returns the
// outcomes of all agents, as one process would have computed them.
#include <memory>
#include <vector>

#include "marsyn/collective.hpp"
#include "marsyn/core/tracking/track_agents.hpp"

namespace marsyn {

struct RankAssignment {
  std::vector<int> split;    // agents tracked by all ranks together, heaviest first
  std::vector<int> rank_of;  // per agent: its rank, or -1 when split
};

// Deterministic in (work, ranks): every rank computes the same assignment.
RankAssignment assign_agents_to_ranks(const std::vector<double>& work, int ranks);

std::vector<AgentOutcome> track_agents_over_ranks(const Problem& problem, const std::vector<NominalTrajectory>& nominal,
                                                  const std::vector<std::shared_ptr<const Tracker>>& trackers,
                                                  const SolveOptions& options, const MemoryBudget& budget,
                                                  const Collective& world);

}  // namespace marsyn
