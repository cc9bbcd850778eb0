#pragma once
// What the outer search did (docs/search.md): each round's action, why it was taken, what it
// changed, and where its time went; why the search stopped, what it tried and what it did not.
// The summary, result.json (`search`) and report.html all read this one record.
#include <string>
#include <vector>

namespace marsyn {

// One parameter the search changed for one agent ("" for the whole team), as text.
struct SearchChange {
  std::string agent;
  std::string what;  // "eps", a tracker's field ("eta_x"), "tracker", "tracker params", "clearance"
  std::string from, to;
};

// The same change made to several agents, once: the agents' names joined ("a1, a2 and 3 more"), or
// "every agent" when all `team_size` agents changed alike; team-wide changes (agent "") and
// changes that differ stay as they are, in the order first made. For what people read (the log
// and the summary); result.json keeps one entry per agent.
std::vector<SearchChange> grouped(const std::vector<SearchChange>& changes, std::size_t team_size);

struct SearchRound {
  int index = 1;            // 1: the first attempt, with the problem as written
  std::string action;       // "first attempt", or the lever (SearchLever names)
  std::string reason;       // the failure of the previous round that called for it
  std::vector<SearchChange> changes;
  int horizon = 0;          // T of this round's plan (the plan kept from an earlier round when not re-planned)
  bool planned = false;     // this round ran the planning stage
  std::string outcome;      // how the round ended
  double plan_time_s = 0, track_time_s = 0, certify_time_s = 0;
  double time_s = 0;        // the round's wall time: deciding, planning, tracking, certifying
  bool undone = false;      // its changes were rolled back (a narrower auto eps that did not verify)
};

struct NotTried {
  std::string lever;
  std::string why;
};

struct SearchReport {
  double time_limit_s = 0;
  std::vector<SearchRound> rounds;
  std::string stop_reason;  // "verified", "time limit", "no lever left", ...
  // Ended by a signal or the hard time limit part-way (result.json status "stopped"), not by
  // running out of levers.
  bool interrupted = false;
  std::vector<NotTried> not_tried;  // levers left when it stopped, each with the reason it did not run
  // Totals over every round (the per-round split is in `rounds`).
  double plan_time_s = 0, track_time_s = 0, certify_time_s = 0, time_s = 0;

  // "tried: enlarge eps x2, refine the tracker x1" or "tried: the first attempt only".
  std::string tried() const;
  // "stopped: <reason> after N rounds and S s; tried: ...; not tried: ... (why)".
  std::string message() const;
};

}  // namespace marsyn
