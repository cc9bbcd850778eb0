#pragma once
// The user's main job (`marsyn solve`): plan -> project -> track every agent (in parallel) ->
// verify -> report, inside the outer search of the paper's Remark 2: when planning fails, the
// horizon grows (inside the planning stage) and then eps shrinks; when an agent's tracking fails,
// an agent of `tracker: auto` first moves to the next tracker that accepted it, otherwise its eps
// is enlarged or its tracker refines its own knobs (Tracker::refine; abcd: finer grids), and the
// problem is re-planned when eps changed. Every attempt is
// recorded with its parameters, outcome and time.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "marsyn/core/verification/certification.hpp"
#include "marsyn/core/planning/plan.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/verification/verification.hpp"

namespace marsyn {

struct SolveOptions {
  int verification_runs = 1000;
  int threads = 2;
  int max_outer_iterations = 4;             // bounded search
  double time_limit_s = 600.0;
  double global_memory_budget_bytes = 2e9;  // the global ABCD baseline is attempted below this
  std::function<void(const std::string&)> log;  // progress lines; may be empty
};

struct Attempt {
  std::string stage;       // "plan", "track <agent>", "verify"
  std::string parameters;  // e.g. "T=104 eps=(0.2,0.2,0.24)"
  std::string outcome;
  double time_s = 0;
};

struct AgentOutcome {
  std::string name;
  std::string tracker;  // the tracker that produced `track`
  TrackResult track;
  std::string controller_file;  // relative to the output folder; empty without a controller
};

struct GlobalAbcdEstimate {
  double state_input_pairs = 0;  // N_g: product grid cells x product inputs over the full domain
  double memory_bytes_estimate = 0;
  std::string status;            // "skipped: ..." or the outcome of an attempt
  double time_s = 0;             // of the attempt
  long long boxes_computed = 0;
};

struct SolveOutcome {
  bool verified = false;
  std::string failure;  // why, when not verified
  Problem problem;      // with the eps / eta / horizon finally used
  planning::PlanOutcome plan;
  std::vector<AgentOutcome> agents;
  CertificationReport certification;  // continuous time: the spec on the period enclosures
  bool certification_ran = false;
  VerificationReport verification;
  bool verification_ran = false;
  GlobalAbcdEstimate global;
  // Per agent: how its tracker was chosen, its assessment, the auto fallbacks not yet used.
  std::vector<AgentTrackers> trackers;
  std::vector<Attempt> attempts;
  double total_time_s = 0;
};

GlobalAbcdEstimate estimate_global_abcd(const Problem& problem);

// Agent `index`'s tracking problem (paper Alg. 1 step 3) along its nominal trajectory.
TrackingProblem tracking_problem(const Problem& problem, int index, const NominalTrajectory& nominal);

// Tracks every agent along its nominal trajectory with its own tracker (trackers[i] for agent
// i, e.g. TrackerInstances::for_agents), agents in parallel (threads from options).
std::vector<AgentOutcome> track_agents(const Problem& problem, const std::vector<NominalTrajectory>& nominal,
                                       const std::vector<std::shared_ptr<const Tracker>>& trackers,
                                       const SolveOptions& options);

// Runs the whole method. Throws only for bad input (unknown plugins); failures are outcomes.
SolveOutcome solve(const LoadedProblem& loaded, const SolveOptions& options);

// Writes result.json, plan.json, one controller file per agent and report.html into out_dir.
nlohmann::json result_json(const SolveOutcome& outcome);
// Returns the files written.
std::vector<std::string> write_solve_outputs(const std::string& out_dir, SolveOutcome& outcome);

}  // namespace marsyn
