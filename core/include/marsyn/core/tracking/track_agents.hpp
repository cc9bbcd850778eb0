#pragma once
// Stage 3's fan-out: every agent tracked along its nominal trajectory by its own tracker, agents
// in parallel over threads (or one after the other with all threads when one agent dominates).
#include <memory>
#include <string>
#include <vector>

#include "marsyn/core/solve_options.hpp"
#include "marsyn/problem.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn {

struct AgentOutcome {
  std::string name;
  std::string tracker;  // the tracker that produced `track`
  TrackResult track;
  std::string controller_file;  // relative to the output folder; empty without a controller
};

// Agent `index`'s tracking problem (paper Alg. 1 step 3) along its nominal trajectory.
TrackingProblem tracking_problem(const Problem& problem, int index, const NominalTrajectory& nominal);

// Tracks every agent along its nominal trajectory with its own tracker (trackers[i] for agent
// i, e.g. TrackerInstances::for_agents), agents in parallel (threads from options), each
// within `budget` (the run's, LoadedProblem::memory_budget: the one the assessments judged).
// Logs one line per agent and a heartbeat every 15 s.
std::vector<AgentOutcome> track_agents(const Problem& problem, const std::vector<NominalTrajectory>& nominal,
                                       const std::vector<std::shared_ptr<const Tracker>>& trackers,
                                       const SolveOptions& options, const MemoryBudget& budget);

// An agent's tracking figures for the log line: the tracker's own counts (abcd: "1200 tube
// cells, "), N_l when the tracker abstracts pairs, then the boxes: "..., N_l 3.1e+05, 812 boxes".
std::string stats_text(const TrackerStats& stats);

}  // namespace marsyn
