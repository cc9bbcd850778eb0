#pragma once
// The outer search's levers (docs/search.md): what each failure of a round may change before the
// next one, in the order tried, each with a cap on its uses so that the search ends even when no
// lever helps. A lever proposes a change on a copy; the orchestrator decides whether it runs.
#include <map>
#include <string>
#include <vector>

#include "marsyn/core/search_report.hpp"
#include "marsyn/core/tracking/tracker_choice.hpp"
#include "marsyn/problem.hpp"

namespace marsyn::search {

enum class Lever { ShrinkEps, FallBack, Refine, EnlargeEps, MoreClearance };
inline constexpr int kLeverCount = 5;

// "(0.2,0.25)": how attempts and changes print a vector.
std::string vector_text(const Eigen::VectorXd& v);

const char* lever_name(Lever lever);
// How often a lever may run in one search (eps x 0.8 four times is 0.41 eps; x 1.25 three times
// is 1.95 eps; four refinements of abcd's grids are 0.32 of them).
int lever_cap(Lever lever);

// What a round failed on, as far as the levers care.
struct Failure {
  enum Kind { None, Plan, NoController, Unsearchable, Certification } kind = None;
  std::string reason;                        // for the log, the report and the stop message
  std::vector<int> agents;                   // NoController: the agents without a controller
  std::map<std::string, double> shortfalls;  // Certification: per requirement, the (negative) margin
};

// The levers that address `failure`, in the order they are tried (none for None and Unsearchable).
std::vector<Lever> levers_for(const Failure& failure);

// What the levers read: the current team, its tracker choices and the plan's extra clearance.
struct Team {
  Problem* problem;
  std::vector<AgentTrackers>* trackers;
  std::map<std::string, double>* extra;
};

struct Proposal {
  Lever lever = Lever::ShrinkEps;
  std::vector<AgentSpec> agents;          // the whole team after the change
  std::vector<AgentTrackers> trackers;    // with the fallbacks it used up removed
  std::map<std::string, double> extra;    // the plan's clearance after the change
  std::vector<SearchChange> changes;
  std::vector<int> changed;               // agents whose tube or tracker changed
  bool replan = false;                    // eps or clearance changed: the robust plan is no longer valid
  std::string why_not;                    // set when the lever has nothing to change
};

// The lever's change for the team, checked with core's agent checks and the trackers' own
// assessments (request: the horizon, tau and memory budget to assess with).
Proposal propose(Lever lever, const Failure& failure, const Team& team, TrackerInstances& instances,
                 const AssessRequest& request);
void apply(const Proposal& proposal, const Team& team);

// Identifies an attempt: every agent's tracker, its parameters, eps and grids, and the plan's
// clearance. Two rounds with the same fingerprint would compute the same thing.
std::string fingerprint(const std::vector<AgentSpec>& agents, const std::map<std::string, double>& extra);

}  // namespace marsyn::search
