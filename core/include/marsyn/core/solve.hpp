#pragma once
// The user's main job (`marsyn solve`): plan -> project -> track every agent (in parallel) ->
// certify -> verify -> report, inside the outer search of the paper's Remark 2 (docs/search.md):
// round after round, while a lever is left and the time limit allows, each round's lever chosen
// from the failure's reason (search_levers.hpp): a failed plan starts from a longer horizon, then
// eps shrinks; a nominal pinned at a bound of U is re-planned inside a smaller U; a tube miss or
// an empty winning set turns the tracker's own declared levers, then eps (in the missed
// coordinate), then `tracker: auto`'s fallback; certification short between the samples gets the
// plan more clearance. An auto eps is narrowed after a verified round (search_auto.hpp). Every
// attempt and every round is recorded with its parameters, outcome and time.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "marsyn/core/verification/certification.hpp"
#include "marsyn/core/planning/plan.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/search_report.hpp"
#include "marsyn/core/solve_options.hpp"
#include "marsyn/core/stage_memory.hpp"
#include "marsyn/core/tracking/global_abcd.hpp"
#include "marsyn/core/tracking/track_agents.hpp"
#include "marsyn/core/tracking/tracker_choice.hpp"
#include "marsyn/core/verification/verification.hpp"

namespace marsyn {

struct Attempt {
  std::string stage;       // "plan", "track <agent>", "certify", "verify", "global ABCD"
  std::string parameters;  // e.g. "planner=altro T=104 eps[a]=(0.2,0.2,0.24)"
  std::string outcome;
  double time_s = 0;
  int horizon = 0;         // T this attempt used (its own: the planning stage lengthens it); 0: none
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
  SearchReport search;  // the rounds, why it stopped, and the time per round
  // Per agent: whether eps and which trackers' fields were auto (docs/parameters.md), and how the search
  // narrowed an auto eps (empty when it did not).
  std::vector<AutoTube> auto_tube;
  std::vector<std::string> auto_notes;
  StageMemory memory;  // what each stage added to the process at its peak (plan: `check`'s prediction beside it)
  double total_time_s = 0;
};

// Runs the whole method. Throws only for bad input (unknown plugins); failures are outcomes.
SolveOutcome solve(const LoadedProblem& loaded, const SolveOptions& options);

}  // namespace marsyn
