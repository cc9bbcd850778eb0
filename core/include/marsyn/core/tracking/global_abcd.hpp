#pragma once
// The global ABCD baseline of the paper's Table 2: one abstraction of the product system over
// its whole domain with a time-invariant reach-avoid controller, attempted only when its size
// fits a memory budget.
#include <functional>
#include <string>

#include "marsyn/core/solve_options.hpp"
#include "marsyn/core/tracking/tracker_choice.hpp"
#include "marsyn/problem.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn {

// The baseline abstracts the product on the agents' own grids, abcd's fields (AgentSpec::fields),
// read here by name: the one place in core that reads a tracker's field (docs/architecture.md,
// "The global ABCD baseline").
inline constexpr const char* kStateGridField = "eta_x";
inline constexpr const char* kInputGridField = "eta_u";
// What the baseline's attempt says it abstracts (SolveOutcome::attempts).
inline constexpr const char* kGlobalAbcdParameters = "eta_x, eta_u of the agents, product domain";

// True when the product cell [lo, hi] may meet the avoid set: interval workspace boxes of every
// agent against each obstacle's bounding box and against each other, in the problem's norm.
// An over-approximation, as a sound controller needs. Formation constraints are not supported.
std::function<bool(const double*, const double*)> product_unsafe(const Problem& problem);

struct GlobalAbcdRun {
  std::string status;  // "controller: x0 winning" / "no controller: ..." / tracker status
  double time_s = 0;
  long long boxes_computed = 0;
  bool initial_state_winning = false;
};

GlobalAbcdRun run_global_abcd(const Problem& problem, const Tracker& tracker, int threads, double memory_budget_bytes);

struct GlobalAbcdEstimate {
  double state_input_pairs = 0;  // N_g: product grid cells x product inputs over the full domain
  double memory_bytes_estimate = 0;
  std::string status;            // "skipped: ..." or the outcome of an attempt
  double time_s = 0;             // of the attempt
  long long boxes_computed = 0;
  bool attempted = false;        // the abstraction ran (else `status` says why not)
};

// The size of the product abstraction over the whole domain (N_g, Table 2), or why it has none.
GlobalAbcdEstimate estimate_global_abcd(const Problem& problem);

// The baseline as `marsyn solve` reports it: estimated, then run with abcd's whole-domain mode
// when it is installed, fits options.global_memory_budget_bytes and the problem allows it.
GlobalAbcdEstimate attempt_global_abcd(const Problem& problem, TrackerInstances& trackers, const SolveOptions& options,
                                       const std::function<void(const std::string&)>& log);

}  // namespace marsyn
