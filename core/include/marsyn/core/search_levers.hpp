#pragma once
// The outer search's levers (docs/search.md): what each failure of a round may change before the
// next one, chosen from the failure's reason (a tube miss in one coordinate, an empty winning
// set, a nominal pinned at a bound of U, a plan that fails), in the order tried, each with a cap
// on its uses so that the search ends even when no lever helps. The trackers' own knobs are
// whatever each tracker declares (Tracker::levers); core keeps no names of them. A lever
// proposes a change on a copy; the orchestrator decides whether it runs.
#include <map>
#include <string>
#include <vector>

#include "marsyn/core/search_report.hpp"
#include "marsyn/core/tracking/tracker_choice.hpp"
#include "marsyn/problem.hpp"

namespace marsyn::search {

enum class Lever {
  LongerHorizon,  // plan: start the planning stage's horizons past the longest it tried
  ShrinkEps,      // plan: every agent's eps x 0.8
  TightenInput,   // a failed agent's nominal sits at a bound of U: re-plan inside a smaller U
  TrackerLever,   // one of the failed agents' trackers' own knobs, by its declared name
  EpsInCoordinate,  // a tube miss: eps x 1.25 in the missed coordinate only
  FallBack,       // tracker: auto: the next tracker that accepted the agent
  EnlargeEps,     // the failed agents' eps x 1.25 in every coordinate
  MoreClearance,  // certification short between the samples: clearance where it fell short
  // A small tube miss (at most kSmallMiss of eps): eps widened in the missed coordinate by the
  // miss plus a margin, and by the same factor in the coordinates at the tube's edge
  // (kNearEdge); the plan is kept when the exact check passes with the wider tubes.
  WidenForMiss,
};

// A miss this small (a share of eps in its coordinate) is closed by widening the tube at once:
// the tracker all but succeeded, and a wider tube costs one exact check of the existing plan,
// where the tracker's knobs cost one tracking each, doubling (docs/search.md).
inline constexpr double kSmallMiss = 0.05;
// The widening: eps_c + the miss x kMissFactor + kMissMargin x eps_c. The miss is that of the first
// step that left the tube; later steps can miss by more, hence twice the miss and 1 % of eps.
inline constexpr double kMissFactor = 2.0;
inline constexpr double kMissMargin = 0.01;
// eps_c after the widening for a miss of `amount` (state units).
double widened_eps(double eps, double amount);
// A coordinate whose verified sets came this near its eps before the miss (TrackFailure::tube_use)
// is widened with the missed one, by the same factor: it would miss next (a drone's vy after vx),
// and each round that finds it costs a tracking of every failed agent.
inline constexpr double kNearEdge = 1.0 - kSmallMiss;

// A lever as tried: its kind and, for TrackerLever, the tracker's own name for it.
struct LeverChoice {
  Lever lever = Lever::ShrinkEps;
  std::string tracker_lever;
  bool operator==(const LeverChoice&) const = default;
};

// "(0.2,0.25)": how attempts and changes print a vector.
std::string vector_text(const Eigen::VectorXd& v);
// "{substeps: 4}": a tracker's parameters as attempts and changes print them.
std::string params_text(const Params& p);
// What a lever (or the automatic eps) changed in an agent, field by field, appended to `out`:
// the tracker or its parameters, eps, and the trackers' own fields by name.
void describe(const AgentSpec& before, const AgentSpec& after, std::vector<SearchChange>& out);

// "shrink eps (x 0.8 or less) and re-plan", "the tracker's finer state grid", ...
std::string lever_name(const LeverChoice& lever);
// How often a lever may run in one search (eps x 0.8 four times is 0.41 eps; x 1.25 three times
// is 1.95 eps; each tracker lever four times).
int lever_cap(Lever lever);

// The share of the input range the nominal may use after k uses of TightenInput on one agent:
// 0.8, 0.6 (the feedback keeps 20 %, then 40 % of U's half-range around the nominal's own bound).
double input_share_after(int uses);
inline constexpr int kInputShareLevels = 2;
// An agent's next share after `share` (the next level below it), or `share` when none is left.
double next_input_share(double share);

// What a round failed on, as far as the levers care.
struct Failure {
  enum Kind { None, Plan, NoController, Unsearchable, Certification } kind = None;
  std::string reason;                        // for the log, the report and the stop message
  std::vector<int> agents;                   // NoController: the agents without a controller
  std::map<std::string, double> shortfalls;  // Certification: per requirement, the (negative) margin
  // NoController: per agent of `agents`, the tracker's own reason and the share of the nominal's
  // steps on which some input sits at a bound of U (measured by core).
  std::vector<TrackFailure> why;
  std::vector<double> nominal_saturation;
  // NoController: per agent of `agents`, a tube miss as a share of eps in its coordinate
  // (amount / eps_c), 0 when the failure is not a miss in one coordinate (measured by core).
  std::vector<double> miss_share;
  int longest_horizon = 0;                   // Plan: the longest horizon the planning stage tried
  // Plan: why the planning stage found that a longer horizon cannot help (PlanOutcome::
  // horizon_blocked); empty when it did not judge so.
  std::string horizon_blocked;
  // Plan: the shortfall at the samples is more than twice every agent's largest eps, so no
  // narrower tube can close it (a tube gives back at most its eps, a pair twice that).
  bool beyond_eps = false;
  // Plan: below 1 when the starts are too crowded for the tubes at any horizon
  // (planning::start_eps_factor): only a narrower tube helps then.
  double start_eps_factor = 1.0;
  // Plan: below 1 when a formation's tolerance is within what the tubes alone can change
  // (planning::formation_eps_factor): a longer horizon cannot help either.
  double formation_eps_factor = 1.0;
  // The factor on eps that leaves every goal room for the tubes (planning::goal_eps_factor):
  // a longer horizon cannot help either.
  double goal_eps_factor = 1.0;
  // Plan: below 1 when the plan's worst requirement is an agent against an obstacle that, with a
  // neighbour, leaves a gap closed to that agent at every horizon (planning::gap_eps_factor): the
  // factor on eps that opens it. A longer horizon cannot; a narrower tube can.
  double gap_eps_factor = 1.0;
};

// Whether the failed agent `w` (an index into failure.agents) missed its tube by a small share of
// eps (0 < miss_share <= kSmallMiss).
bool small_miss(const Failure& failure, std::size_t w);


// The levers that address `failure`, in the order they are tried (none for None and
// Unsearchable). `declared`: the failed agents' trackers' own levers (Tracker::levers), in order.
std::vector<LeverChoice> levers_for(const Failure& failure, const std::vector<TrackerLever>& declared);

// What the levers read and change: the current team, its tracker choices, the plan's extra
// clearance, each agent's share of U for the nominal, and the horizon the planning starts from.
struct Team {
  Problem* problem;
  std::vector<AgentTrackers>* trackers;
  std::map<std::string, double>* extra;
  std::vector<double>* input_share;
  int* min_horizon;
};

struct Proposal {
  LeverChoice lever;
  std::vector<AgentSpec> agents;          // the whole team after the change
  std::vector<AgentTrackers> trackers;    // with the fallbacks it used up removed
  std::map<std::string, double> extra;    // the plan's clearance after the change
  std::vector<double> input_share;
  int min_horizon = 0;
  std::vector<SearchChange> changes;
  std::vector<int> changed;               // agents whose tube or tracker changed
  bool replan = false;                    // the robust plan is no longer valid
  // Only wider tubes: the plan stays valid when the exact check passes with them (the search
  // re-checks it, and re-plans only when it does not).
  bool recheck = false;
  std::string why_not;                    // set when the lever has nothing to change
};

// The lever's change for the team, checked with core's agent checks and the trackers' own
// assessments (request: the horizon, tau and memory budget to assess with). `uses`: how often
// the lever ran before.
Proposal propose(const LeverChoice& lever, const Failure& failure, const Team& team, TrackerInstances& instances,
                 const AssessRequest& request, int uses = 0);
void apply(const Proposal& proposal, const Team& team);
// The team as it is, as a proposal that changes nothing (what levers and merges start from).
Proposal unchanged(const Team& team);

// Identifies an attempt: every agent's tracker, its parameters, eps and grids, its share of U,
// the plan's clearance and the horizon the planning starts from. Two rounds with the same
// fingerprint would compute the same thing.
std::string fingerprint(const std::vector<AgentSpec>& agents, const std::map<std::string, double>& extra,
                        const std::vector<double>& input_share = {}, int min_horizon = 0);

}  // namespace marsyn::search
