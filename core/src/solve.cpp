#include "marsyn/core/solve.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "marsyn/number_text.hpp"
#include "marsyn/stopwatch.hpp"
#include "marsyn/core/verification/run_progress.hpp"
#include "marsyn/core/planning/solver_progress.hpp"
#include "marsyn/core/planning/goal_room.hpp"
#include "marsyn/core/planning/workspace_gaps.hpp"
#include "marsyn/core/mpi/plan_broadcast.hpp"
#include "marsyn/core/search_auto.hpp"
#include "marsyn/core/search_levers.hpp"
#include "marsyn/core/search_rank.hpp"
#include "marsyn/core/planning/plan_io.hpp"
#include "marsyn/core/problem/config_error.hpp"
#include "marsyn/core/tracking/tracker_choice.hpp"
#include "marsyn/core/setup.hpp"
#include "marsyn/core/problem/agent_checks.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/problem/tracker_fields.hpp"
#include "marsyn/core/tracking/global_abcd.hpp"
#include "marsyn/core/tracking/tracking_memory.hpp"

namespace marsyn {
namespace {

// Wider tubes for one agent before its tracker's own knobs that keep the plan go first.
constexpr int kWidenBeforeKnobs = 2;
// An agent's tracker knobs that did not help it (helped()) before another tracker goes first: a
// knob rarely closes a miss the one before it left (30 of the 400-robot field's unicycles went
// through five knob rounds, 15-22 s each, before abcd gave all of them controllers in 4 s).
constexpr int kKnobsBeforeFallback = 1;

// A large team's plan frees gigabytes of small blocks (rows, multipliers) that glibc keeps in
// the process, so tracking and verification came on top of the plan's peak instead of reusing
// it: handing them back to the system makes the run's peak the largest stage's, not their sum
// (400 unicycles: 607 -> 448 MB; 1000: 2759 -> 2219 MB).
void return_freed_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

using search::Failure;
using search::Lever;
using search::LeverChoice;

// An attempt's parameters for one agent: its tracker, eps, and the trackers' fields it has
// (abcd's grid).
std::string agent_parameters(const AgentSpec& a) {
  std::string p = "tracker=" + a.tracker.name + (a.tracker.params.values().empty() ? "" : search::params_text(a.tracker.params)) +
                  " eps=" + search::vector_text(a.tube.eps);
  for (const auto& f : a.fields.items)
    if (f.value.size()) p += " " + f.name + "=" + search::vector_text(f.value);
  return p;
}

std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g s", s);
  return buf;
}

std::string changes_text(const std::vector<SearchChange>& changes) {
  std::string s;
  for (const auto& c : changes)
    s += (s.empty() ? "" : "; ") + (c.agent.empty() ? "" : c.agent + " ") + c.what + " " + c.from + " -> " + c.to;
  return s;
}

// The search's run through the stages, round by round (docs/search.md). One object per solve().
class Search {
 public:
  // The stages run through `setup` (its planners, its trackers, its budget).
  Search(Setup& setup, const SolveOptions& opt, SolveOutcome& out)
      : setup_(setup), loaded_(setup.loaded()), opt_(stoppable(opt)), out_(out), pb_(out.problem), instances_(setup.trackers()) {
    out_.search.time_limit_s = opt.time_limit_s;
    input_share_.assign(pb_.agents.size(), 1.0);
    out_.auto_tube = loaded_.auto_tube;
  }

  // Runs rounds until every agent has a certified controller or the search stops; returns
  // whether the last round left every agent with a controller (certified when continuous).
  bool run(const Stopwatch& t_start);

 private:
  // The options the stages run with: the caller's stop request (a signal) or the time limit,
  // whichever comes first, ends tracking between agents and planning between horizons.
  SolveOptions stoppable(const SolveOptions& opt) {
    SolveOptions o = opt;
    // Called from the tracking threads too: the cause is an atomic code, its text made later.
    o.stop = [outer = opt.stop, limit = opt.time_limit_s, this] {
      if (outer && outer()) {
        cause_ = 1;
        return true;
      }
      if (clock_.seconds() > limit) {
        int none = 0;
        cause_.compare_exchange_strong(none, 2);
        return true;
      }
      return false;
    };
    return o;
  }
  bool stopping() const {
    // Over MPI rank 0 decides, so that every rank leaves the loop at the same round.
    return rank0_says(opt_.stop && opt_.stop());
  }
  void log(const std::string& s) const {
    if (opt_.log) opt_.log(s);
  }
  // Over MPI every rank runs the loop in lock step; rank 0's clock decides what time allows.
  bool rank0_says(bool mine) const {
    if (!opt_.cluster || opt_.cluster->size() <= 1) return mine;
    std::vector<std::uint8_t> b{static_cast<std::uint8_t>(mine ? 1 : 0)};
    opt_.cluster->broadcast(b, 0);
    return b.at(0) != 0;
  }
  bool root() const { return !opt_.cluster || opt_.cluster->rank() == 0; }
  // Over MPI: rank 0's plan's visit knots to every rank (they judge the stages at them).
  void broadcast_visits();
  AssessRequest ask() const { return {pb_.horizon, pb_.tau, loaded_.memory_budget}; }

  Failure plan(SearchRound& round, double time_left);
  // The problem with each agent's U narrowed to its input share, in `tightened`; false (and
  // `tightened` untouched) when every agent may use all of U.
  bool tighten_inputs(Problem& tightened) const { return tighten_inputs(pb_.agents, tightened); }
  // The same for the team `agents` (the search's own, or one with wider tubes to check).
  bool tighten_inputs(const std::vector<AgentSpec>& agents, Problem& tightened) const;
  GlobalPlan clamped_last_plan(const Problem& planned) const;
  void record_plan_attempts();
  Failure track(SearchRound& round);
  // The agents whose controller does not carry over (see tracked_params_), in agent order.
  std::vector<int> agents_to_track() const;
  // The tracked agents' attempts recorded; the failure, if an agent has no controller.
  Failure tracking_failure(const std::vector<int>& redo);
  Failure certify(SearchRound& round);
  // The next round's lever, applied (replan: whether it invalidated the plan), or false (with
  // stop_reason and not_tried set).
  bool next_round(const Failure& failure, double elapsed, SearchRound& next, bool& replan);
  // A lever's proposal for `failure` and its predicted time, when it may run (cap, help, change,
  // novelty, time); false with the reason in the report's not_tried otherwise.
  bool candidate(const LeverChoice& lever, const Failure& failure, const std::vector<TrackerLever>& declared, double elapsed,
                 search::Candidate& out);
  // solve --resume: the folder's plan and controllers, when the plan is still eps-robust with the
  // tubes recorded there; true when round 1 can start from them (no planning).
  bool resume(const std::string& dir, SearchRound& round);
  // Every lever that may run for `failure` (levers_for's order), with its proposal and time.
  std::vector<search::Candidate> candidates_for(const Failure& failure, double elapsed);
  // A tracking failure: each failed agent's best lever (search_rank.hpp), merged into one round.
  bool agents_round(const Failure& failure, double elapsed, SearchRound& next, bool& replan);
  // The candidate an agent's failure picks first (the wider tube behind the tracker's knobs
  // once it was used kWidenBeforeKnobs times); -1: none.
  int first_choice(const std::vector<search::Candidate>& candidates, int agent);
  // `best`, or another tracker in its place when it is a knob and the agent's knobs have not
  // helped it kKnobsBeforeFallback times.
  int fallback_over_knob(const std::vector<search::Candidate>& candidates, int best, int agent);
  // The agents whose first choice is a wider tube that keeps the plan, all checked at once; empty
  // when that check fails (each agent is then checked alone).
  std::set<int> wider_tubes_keep_plan(const Failure& failure, const std::vector<std::vector<search::Candidate>>& all,
                                      const std::vector<int>& bests);
  // Applies the picks (one per agent, or one for the team) as the next round.
  bool take(const std::vector<search::Proposal>& picks, const std::vector<std::string>& names, const Failure& failure,
            SearchRound& next, bool& replan, const std::vector<std::string>& who = {});
  // The exact check of the current plan with the (just widened) tubes; true when it passes.
  bool keeps_plan(std::string& said);
  // Where agent i's nominal ends outside its goal shrunk by `a`'s eps (a necessary condition of
  // the exact check, read off the plan's last knot): what and by how much; empty otherwise.
  std::string goal_conflict(const AgentSpec& a, int i) const;
  // The exact check of the current plan with `agents` in place of the team's (their tubes).
  bool robust_with(const std::vector<AgentSpec>& agents, planning::RobustCheck& check);
  double last_check_s_ = 0;  // the last such check's time, for the estimates
  void stop_without_lever(const Failure& failure);
  // After a stop: "; the best lever untried: <lever> (about S)" for the round's failure, what a
  // resumed or longer run would do next; empty when no lever applies.
  std::string best_untried(const Failure& failure);
  // A planning failure with a planner the file named: the default planner, once.
  bool default_planner(const Failure& failure, double elapsed, SearchRound& next);
  // Marks each knob the last round turned unhelpful when no agent it changed got further.
  void judge_last_knobs(const Failure& failure);
  // The failed agents' trackers' own levers, each name once.
  std::vector<TrackerLever> declared_levers(const Failure& failure);
  // The tracker knob this round turns and its agents' failures before it, for judge_last_knob.
  void remember_knob(const std::string& name, const search::Proposal& p, const Failure& failure);
  // After a round in which every agent got a controller: narrows the auto agents' eps to the
  // tubes their controllers kept (search_auto.hpp), saving this round to fall back on; false when
  // no auto eps would narrow, the iterations are used up or time does not allow.
  bool narrow_auto_eps(double elapsed, SearchRound& next);
  // A saved round, back (the narrower auto eps failed; a re-plan for a tracker found no plan).
  struct Saved;
  Saved snapshot(int round) const;
  void restore(const Saved& s);
  // Seconds the round a proposal asks for would take, from the last rounds' times.
  // cost: the tracker's declared cost factor of a tracker lever (1 otherwise).
  double estimate(const search::Proposal& p, double cost = 1);
  // The key a lever's uses are counted under when it is counted per agent.
  std::string uses_key(const std::string& lever, int agent) const { return lever + " @" + pb_.agents[agent].name; }

  Stopwatch clock_;            // from the search's start: the hard time limit
  std::atomic<int> cause_{0};  // why the stop predicate said yes: 1 a signal, 2 the time limit
  std::string cause_text() const {
    return cause_ == 1 ? "a stop was requested (SIGINT or SIGTERM)"
                       : "the time limit (" + seconds(opt_.time_limit_s) + ") was reached";
  }
  Setup& setup_;
  const LoadedProblem& loaded_;
  const SolveOptions opt_;
  SolveOutcome& out_;
  Problem& pb_;
  TrackerInstances& instances_;
  std::map<std::string, double> extra_;  // per constraint: grows where certification fell short
  std::set<std::string> seen_;           // fingerprints of the attempts made
  std::map<std::string, int> uses_;      // per lever (by name): the rounds it ran
  std::map<int, int> knob_misses_;       // per agent: the rounds a tracker's own knob did not help it (helped())
  std::vector<double> input_share_;      // per agent: the share of U the nominal may use (1: all)
  int min_horizon_ = 0;                  // the horizon the planning starts from at least (0: the file's)
  // eps: auto (search_auto.hpp): the rounds that narrowed it, and the last verified round's state.
  int auto_rounds_ = 0;
  bool trial_ = false;  // the running round narrowed an auto eps
  struct Saved {
    planning::PlanOutcome plan;
    std::vector<AgentOutcome> agents;
    CertificationReport certification;
    bool certification_ran = false;
    std::vector<AgentSpec> specs;
    std::vector<AgentTrackers> trackers;
    std::map<std::string, double> extra;
    std::vector<double> input_share;
    int min_horizon = 0, horizon = 0, round = 0;
  } saved_;
  // The round before a re-plan chosen for a tracker failure (U tightened, a wider tube): when
  // that re-plan finds no eps-robust plan, the search goes back to it and its failure, and the
  // lever counts as unhelpful, instead of following the planning failure the lever caused
  // (shrinking eps and lengthening the horizon, the opposite of what the tracker asked for).
  struct ReplanBase {
    bool active = false;
    std::vector<std::string> levers;  // the re-planning levers of the round (one per agent at most)
    Failure failure;
    Saved saved;
  } replan_base_;
  search::Team team() { return {&pb_, &out_.trackers, &extra_, &input_share_, &min_horizon_}; }
  std::string fingerprint() const { return search::fingerprint(pb_.agents, extra_, input_share_, min_horizon_); }
  double last_plan_s_ = 0, last_track_s_ = 0, last_certify_s_ = 0;
  double full_track_s_ = 0;  // the last tracking of every agent
  // What the last tracking ran with, per agent: its parameters (agent_parameters) and nominal. An
  // agent with a controller whose both are unchanged keeps its controller (nothing it depends on
  // changed); only the others are tracked again.
  std::vector<std::string> tracked_params_;
  std::vector<NominalTrajectory> tracked_nominal_;
  // The lever of the running round when it was one of a tracker's own knobs (no re-plan), the
  // agents it changed and their failures before it: if none of them got better the lever is not
  // turned again (its cap is spent), rather than repeated on the hope that more of it helps.
  struct LastKnob {
    std::string name;
    std::map<int, TrackFailure> before;
  };
  std::vector<LastKnob> last_knobs_;  // one per knob the last round turned (agents may differ)
  bool multi_agent_ = false;          // choosing per agent for several: refusals name the agent
  // This round's cheapest lever refused for time alone, for the stop message.
  struct {
    std::string lever;
    double s = -1;
  } unfit_;
  std::map<std::string, std::string> unhelpful_;  // lever name -> why it is not turned again
  // The plan stage's warm start: the last feasible plan, when the next re-plan follows a tracker
  // failure (the same team with a changed tube or U: the previous plan is a good initial guess).
  bool warm_from_last_ = false;
  bool closed_gaps_said_ = false;  // the plan stage logs the closed gaps in the first round only
};

Failure Search::plan(SearchRound& round, double time_left) {
  planning::PlanSearchOptions po;
  po.time_limit_s = std::max(1.0, time_left);
  po.log = [&](const std::string& s) { log("[plan] " + s); };
  po.stop = opt_.stop;
  po.log_closed_gaps = !closed_gaps_said_;
  closed_gaps_said_ = true;
  po.progress = [p = std::make_shared<planning::SolverProgress>(opt_.log, opt_.live)](const PlanProgress& x) { (*p)(x); };
  po.assembly.extra = extra_;
  log("[plan] " + pb_.planner.name + " on the product system (" + std::to_string(pb_.product_state_dim()) + " state" +
      (pb_.product_state_dim() == 1 ? "" : "s") + ", " + std::to_string(pb_.product_input_dim()) + " input" +
      (pb_.product_input_dim() == 1 ? "" : "s") + ")");
  if (min_horizon_ > pb_.horizon) pb_.horizon = min_horizon_;
  Problem tightened;
  const Problem& planned = tighten_inputs(tightened) ? tightened : pb_;
  if (warm_from_last_ && out_.plan.feasible && !out_.plan.plan.u.empty()) {
    po.warm_start = clamped_last_plan(planned);
    po.assembly.visits = out_.plan.visits;  // and its visit knots, the first ones tried
    log("[plan] warm start: the previous plan (T = " + std::to_string(out_.plan.plan.horizon()) + ")");
  }
  warm_from_last_ = false;
  const Stopwatch t;
  if (root()) {
    const StageWatch watch(out_.memory.plan);
    out_.plan = setup_.plan(planned, std::move(po));
  }
  return_freed_memory();
  if (opt_.cluster) mpi::broadcast_plan(*opt_.cluster, out_.plan);  // what the other ranks need of it
  if (opt_.cluster) broadcast_visits();
  round.planned = true;
  round.plan_time_s = last_plan_s_ = t.seconds();
  record_plan_attempts();
  round.horizon = out_.plan.horizon;
  if (!out_.plan.feasible) {
    Failure f{Failure::Plan, "planning failed: " + out_.plan.check.message, {}, {}};
    for (const auto& pa : out_.plan.attempts) f.longest_horizon = std::max(f.longest_horizon, pa.horizon);
    f.horizon_blocked = out_.plan.horizon_blocked;
    if (!f.horizon_blocked.empty()) f.reason += "; no longer horizon: " + f.horizon_blocked;
    double eps = 0.0;
    for (const auto& a : pb_.agents) eps = std::max(eps, a.tube.eps.maxCoeff());
    f.beyond_eps = out_.plan.check.sampled_margin < -2.0 * eps;
    if (out_.plan.attempts.empty()) {
      f.start_eps_factor = planning::start_eps_factor(pb_);
      f.goal_eps_factor = planning::goal_eps_factor(pb_);
    }
    f.formation_eps_factor = planning::formation_eps_factor(pb_);
    f.gap_eps_factor = planning::gap_eps_factor(pb_, out_.plan.check);
    return f;
  }
  if (!out_.plan.nominal.empty()) pb_.horizon = out_.plan.horizon;
  extra_ = out_.plan.extra;  // a later re-plan keeps the clearance this one needed
  return {};
}

void Search::broadcast_visits() {
  if (opt_.cluster->size() <= 1) return;
  std::vector<std::uint8_t> b;
  auto put = [&](int v) {
    for (int s = 0; s < 32; s += 8) b.push_back(static_cast<std::uint8_t>((static_cast<unsigned>(v) >> s) & 0xffu));
  };
  if (root()) {
    const planning::MissionSchedule& v = out_.plan.visits;
    put(v.horizon);
    put(v.feasible ? 1 : 0);
    put(static_cast<int>(v.visit.size()));
    for (const auto& a : v.visit) {
      put(static_cast<int>(a.size()));
      for (int k : a) put(k);
    }
  }
  opt_.cluster->broadcast(b, 0);
  if (root()) return;
  std::size_t at = 0;
  auto get = [&] {
    unsigned v = 0;
    for (int s = 0; s < 32; s += 8) v |= static_cast<unsigned>(b.at(at++)) << s;
    return static_cast<int>(v);
  };
  planning::MissionSchedule& v = out_.plan.visits;
  v = {};
  v.horizon = get();
  v.feasible = get() != 0;
  v.visit.resize(static_cast<std::size_t>(get()));
  for (auto& a : v.visit) {
    a.resize(static_cast<std::size_t>(get()));
    for (int& k : a) k = get();
  }
}

bool Search::tighten_inputs(const std::vector<AgentSpec>& agents, Problem& tightened) const {
  // U tightened for the nominal (docs/search.md): the planner sees the smaller box, the trackers
  // the file's, so the feedback keeps the rest of U around the nominal's input.
  if (std::none_of(input_share_.begin(), input_share_.end(), [](double s) { return s < 1; })) return false;
  tightened = pb_;
  tightened.agents = agents;
  for (std::size_t i = 0; i < tightened.agents.size(); ++i) {
    Box& u = tightened.agents[i].input_bounds;
    const Eigen::VectorXd c = 0.5 * (u.lo + u.hi), h = 0.5 * input_share_[i] * (u.hi - u.lo);
    u.lo = c - h;
    u.hi = c + h;
  }
  return true;
}

GlobalPlan Search::clamped_last_plan(const Problem& planned) const {
  // The previous plan, its inputs clamped to the U the planner now sees: its horizon, and
  // the planner refines it instead of starting cold (planning::PlanSearchOptions::warm_start).
  GlobalPlan w = out_.plan.plan;
  Eigen::VectorXd lo(planned.product_input_dim()), hi(planned.product_input_dim());
  for (std::size_t i = 0, o = 0; i < planned.agents.size(); o += planned.agents[i].m(), ++i) {
    lo.segment(o, planned.agents[i].m()) = planned.agents[i].input_bounds.lo;
    hi.segment(o, planned.agents[i].m()) = planned.agents[i].input_bounds.hi;
  }
  for (auto& u : w.u)
    if (u.size() == lo.size()) u = u.cwiseMax(lo).cwiseMin(hi);
  return w;
}

void Search::record_plan_attempts() {
  // Each horizon the planning stage tried, with its own T.
  for (const auto& pa : out_.plan.attempts) {
    std::ostringstream params;
    params << "planner=" << pa.planner << " T=" << pa.horizon;
    if (!extra_.empty()) params << " extra clearance for " << extra_.size() << " constraint(s)";
    for (std::size_t i = 0; i < pb_.agents.size(); ++i) {
      params << " eps[" << pb_.agents[i].name << "]=" << search::vector_text(pb_.agents[i].tube.eps);
      if (input_share_[i] < 1) params << " U share[" << pb_.agents[i].name << "]=" << input_share_[i];
    }
    const bool robust = pa.check.passed;
    out_.attempts.push_back({"plan", params.str(),
                             robust ? "feasible, smallest robust margin " + number_text(pa.check.min_margin, 3)
                                    : std::string(to_string(pa.status)) + (pa.check.message.empty() ? "" : ": " + pa.check.message),
                             pa.solve_time_s, pa.horizon});
  }
}

Failure Search::track(SearchRound& round) {
  const Stopwatch t;
  // A later round starts after the plan's re-check with wider tubes and the certification: what
  // they freed goes back first, or the round's peak counts it as tracking's (1000 unicycles, four
  // rounds: 489 MB added beside 442 MB of controllers and working memory predicted).
  return_freed_memory();
  const StageWatch watch(out_.memory.track);
  const std::size_t N = pb_.agents.size();
  const std::vector<int> redo = agents_to_track();
  // The controllers being replaced go first: kept beside their successors, a full round after a
  // re-plan held every agent's controller twice (tracking's memory figure counts them once).
  if (redo.size() == N || out_.agents.size() != N) {
    out_.agents.clear();
    out_.agents.shrink_to_fit();
    out_.agents = setup_.track(pb_, out_.plan.nominal, opt_);
  } else {
    for (int i : redo) out_.agents[static_cast<std::size_t>(i)].track.controller.reset();
    // Only the agents whose nominal or parameters changed, or that have no controller yet.
    Problem sub = pb_;
    sub.agents.clear();
    std::vector<NominalTrajectory> nominal;
    for (int i : redo) {
      sub.agents.push_back(pb_.agents[i]);
      nominal.push_back(out_.plan.nominal[i]);
    }
    log("[track] " + std::to_string(N - redo.size()) + " agent(s) keep their controllers (nominal and parameters unchanged); tracking " +
        std::to_string(redo.size()));
    std::vector<AgentOutcome> fresh = redo.empty() ? std::vector<AgentOutcome>{} : setup_.track(sub, nominal, opt_);
    for (std::size_t w = 0; w < redo.size(); ++w) out_.agents[redo[w]] = std::move(fresh[w]);
  }
  tracked_params_.resize(N);
  tracked_nominal_.resize(N);
  for (std::size_t i = 0; i < N; ++i) {
    tracked_params_[i] = agent_parameters(pb_.agents[i]);
    if (i < out_.plan.nominal.size()) tracked_nominal_[i] = out_.plan.nominal[i];
  }
  round.track_time_s = last_track_s_ = t.seconds();
  if (redo.size() == N) full_track_s_ = last_track_s_;
  log("[track] all agents in " + number_text(round.track_time_s, 3) + " s");
  return tracking_failure(redo);
}

std::vector<int> Search::agents_to_track() const {
  std::vector<int> redo;
  for (std::size_t i = 0; i < pb_.agents.size(); ++i) {
    const bool keep = i < out_.agents.size() && out_.agents[i].track.controller && i < tracked_params_.size() &&
                      tracked_params_[i] == agent_parameters(pb_.agents[i]) && i < tracked_nominal_.size() &&
                      i < out_.plan.nominal.size() && tracked_nominal_[i].x == out_.plan.nominal[i].x &&
                      tracked_nominal_[i].u == out_.plan.nominal[i].u;
    if (!keep) redo.push_back(static_cast<int>(i));
  }
  return redo;
}

Failure Search::tracking_failure(const std::vector<int>& redo) {
  Failure f{Failure::NoController, "no controller for", {}, {}};
  // A synthesis the run's stop cut short (TrackOptions::stop) ended for no reason of its own: it
  // counts as not tracked, as the agents never started do, so that the stop message still names
  // the lever that would have come next. Every rank asks (a collective), the answer is rank 0's.
  const bool cut_short = stopping();
  std::string cut;  // the agents whose synthesis the stop cut short
  for (std::size_t i = 0; i < out_.agents.size(); ++i) {
    const auto& r = out_.agents[i].track;
    const bool kept = std::find(redo.begin(), redo.end(), static_cast<int>(i)) == redo.end();
    if (!kept)
      out_.attempts.push_back({"track " + out_.agents[i].name, agent_parameters(pb_.agents[i]),
                               std::string(to_string(r.status)) + (r.message.empty() ? "" : ": " + r.message),
                               r.stats.abstraction_time_s + r.stats.synthesis_time_s, pb_.horizon});
    if (r.status == TrackerStatus::ControllerFound) continue;
    // Only "no controller" is a reason to change parameters; bad input or an exhausted budget
    // would fail the same way again.
    if (r.status != TrackerStatus::NoController && !(cut_short && r.status == TrackerStatus::ResourceLimit))
      return {Failure::Unsearchable,
              "tracking " + pb_.agents[i].name + ": " + to_string(r.status) + (r.message.empty() ? "" : ": " + r.message),
              {}, {}};
    f.agents.push_back(static_cast<int>(i));
    f.reason += " " + pb_.agents[i].name;
    if (r.status == TrackerStatus::ResourceLimit) cut += (cut.empty() ? "" : " ") + pb_.agents[i].name;
    f.why.push_back(r.failure);
    const int c = r.failure.coordinate;
    const Eigen::VectorXd& eps = pb_.agents[i].tube.eps;
    f.miss_share.push_back(r.failure.kind == TrackFailureKind::TubeMiss && c >= 0 && c < eps.size() && eps[c] > 0
                               ? r.failure.amount / eps[c]
                               : 0.0);
    f.nominal_saturation.push_back(
        i < out_.plan.nominal.size() ? planning::saturation_share(out_.plan.nominal[i].u, pb_.agents[i].input_bounds) : 0.0);
  }
  if (!cut.empty()) f.reason += "; the stop cut short the synthesis of " + cut;
  return f.agents.empty() ? Failure{} : f;
}

Failure Search::certify(SearchRound& round) {
  // The stages at the plan's visit knots (docs/tasks.md): the problem with each stage's window
  // narrowed to its knot, so the certifier judges exactly the knots the plan was checked at.
  {
    const StageWatch watch(out_.memory.certify);
    out_.certification = setup_.certify(planning::with_visits(pb_, out_.plan.visits), out_.agents);
  }
  out_.certification_ran = true;
  round.certify_time_s = last_certify_s_ = out_.certification.time_s;
  log("[certify] " + out_.certification.message);
  out_.attempts.push_back({"certify", std::to_string(out_.certification.enclosures) + " period enclosures",
                           out_.certification.message, out_.certification.time_s, pb_.horizon});
  if (out_.certification.certified) return {};
  const double shortfall = -out_.certification.min_margin;
  Failure f{Failure::Certification, "certification failed: " + out_.certification.message, {}, {}};
  // A non-finite or non-positive shortfall names nothing to clear: no lever addresses it.
  if (!std::isfinite(shortfall) || !(shortfall > 0)) f.kind = Failure::Unsearchable;
  else f.shortfalls = out_.certification.shortfalls;
  return f;
}

double Search::estimate(const search::Proposal& p, double cost) {
  // Tracking scales with the trackers' own work estimates (a finer grid costs more) and with
  // what a tracker declared its lever costs. A round that keeps the plan re-tracks only the
  // changed agents: each from its own last tracking time, spread over the threads.
  double ratio = std::max(1.0, cost), own = 0, longest = 0;
  for (int i : p.changed) {
    const double before = assess_tracker(instances_, pb_.agents[i].tracker, pb_.agents[i], ask()).work_s;
    const double after = assess_tracker(instances_, p.agents[i].tracker, p.agents[i], ask()).work_s;
    // Another tracker is judged by the two trackers' own estimates, below 1 too (abcd's 1.5 s
    // where the funnel took 45 s); the same tracker's knob costs at least what it declares.
    const bool other = p.agents[i].tracker.name != pb_.agents[i].tracker.name;
    const double r = before > 0 && after > 0 && other ? std::max(0.01, after / before)
                                                      : std::max(std::max(1.0, cost), before > 0 && after > 0 ? after / before : 1.0);
    ratio = std::max(ratio, r);
    const auto at = static_cast<std::size_t>(i);
    const double last = at < out_.agents.size()
                            ? out_.agents[at].track.stats.abstraction_time_s + out_.agents[at].track.stats.synthesis_time_s
                            : 0.0;
    // Another tracker: its own estimate, absolute. Scaling this agent's measured time by the two
    // trackers' estimates multiplied the funnel's underestimate (one pass of 0.04 s where the
    // weight choices and splits took 0.9 s) into abcd "about 450 s" for unicycles it tracks in a
    // few seconds, and the fallback never ran (tests/problems/users2/02).
    const double t = other && after > 0 ? after : (last > 0 ? last : last_track_s_) * r;
    own += t;
    longest = std::max(longest, t);
  }
  const double spread = std::max(longest, own / std::max(1, opt_.threads));
  // A wider tube re-checks the plan first (about as long as the planning stage's own check).
  const double check = p.recheck ? (last_check_s_ > 0 ? last_check_s_ : 0.05 * last_plan_s_) : 0.0;
  if (!p.replan || p.recheck) return check + std::min(spread, last_track_s_ * ratio) + last_certify_s_;
  // A re-plan tracks every agent again.
  return last_plan_s_ + std::max(last_track_s_, full_track_s_) * ratio + last_certify_s_;
}

// Whether an agent's record in result.json (`w`, and `w_base`, `w_per` where W grows with the
// state) states the disturbance bound `tube` has, number for number.
bool same_disturbance(const nlohmann::json& rec, const TubeParams& tube) {
  auto same_vector = [](const nlohmann::json& j, const Eigen::VectorXd& v) {
    if (!j.is_array() || static_cast<Eigen::Index>(j.size()) != v.size()) return false;
    for (Eigen::Index c = 0; c < v.size(); ++c)
      if (!j[static_cast<std::size_t>(c)].is_number() || j[static_cast<std::size_t>(c)].get<double>() != v[c]) return false;
    return true;
  };
  if (!rec.contains("w") || !same_vector(rec["w"], tube.w)) return false;
  if (!tube.state_dependent()) return !rec.contains("w_base") && !rec.contains("w_per");
  if (!rec.contains("w_base") || !same_vector(rec["w_base"], tube.w_base)) return false;
  const nlohmann::json per = rec.value("w_per", nlohmann::json());
  if (!per.is_object() || per.size() != tube.w_growth.size()) return false;
  for (const DisturbanceGrowth& g : tube.w_growth)
    if (!per.contains(g.name) || !same_vector(per[g.name], g.gain)) return false;
  return true;
}

// Agent a's record in an earlier solve's result.json: the eps it was tracked with (into a.tube),
// and whether its controller was made for this problem's initial set and disturbance.
bool read_recorded_tube(const nlohmann::json& j, const std::string& result_file, AgentSpec& a) {
  const nlohmann::json* rec = nullptr;
  if (j.contains("agents") && j["agents"].is_array())
    for (const auto& r : j["agents"])
      if (r.is_object() && r.value("name", "") == a.name) rec = &r;
  if (!rec) throw ConfigError(result_file, 0, 0, "agents", "no record of agent " + a.name + ": the folder is of another problem");
  const auto& e = (*rec)["eps"];
  if (!e.is_array() || static_cast<int>(e.size()) != a.n())
    throw ConfigError(result_file, 0, 0, "agents." + a.name + ".eps", "expected " + std::to_string(a.n()) + " numbers");
  for (int c = 0; c < a.n(); ++c) {
    if (!e[c].is_number() || !(e[c].get<double>() > 0))
      throw ConfigError(result_file, 0, 0, "agents." + a.name + ".eps", "expected positive numbers");
    a.tube.eps[c] = e[c].get<double>();
  }
  // A controller made for another initial set may not accept this one's starts: tracked again.
  // No list of n entries: a point start (zeros); an entry that is not a number matches nothing.
  const nlohmann::json radius = rec->value("x0_radius", nlohmann::json());
  const bool listed = radius.is_array() && static_cast<int>(radius.size()) == a.n();
  bool same = true;
  for (int c = 0; c < a.n(); ++c) {
    const nlohmann::json* r = listed ? &radius[static_cast<std::size_t>(c)] : nullptr;
    same = same && (r ? (r->is_number() ? r->get<double>() : -1.0) : 0.0) == a.x0_half(c);
  }
  // ... and one made for another disturbance bound keeps another tube: tracked again too (a
  // folder from before W was recorded counts as another).
  same = same && same_disturbance(*rec, a.tube);
  return same;
}

// Whether a tracker's knob got an agent further: a controller, a miss later or at least a quarter
// smaller, an empty winning set from an earlier step.
bool helped(const TrackFailure& before, const Failure& now, int agent) {
  const auto it = std::find(now.agents.begin(), now.agents.end(), agent);
  if (it == now.agents.end()) return true;
  const std::size_t w = static_cast<std::size_t>(it - now.agents.begin());
  if (w >= now.why.size()) return false;
  const TrackFailure& after = now.why[w];
  if (after.kind != before.kind || before.step < 0 || after.step < 0) return false;
  if (after.kind == TrackFailureKind::TubeMiss)
    return after.step > before.step || (after.step == before.step && after.amount <= 0.75 * before.amount);
  if (after.kind == TrackFailureKind::EmptyWinningSet) return after.step < before.step;
  return false;
}

std::string miss_text(const TrackFailure& f) {
  if (f.kind == TrackFailureKind::TubeMiss) {
    char b[64];
    std::snprintf(b, sizeof b, "miss %.3g at step %d", f.amount, f.step);
    return b;
  }
  if (f.kind == TrackFailureKind::EmptyWinningSet) return "empty from step " + std::to_string(f.step);
  return "no controller";
}

void Search::judge_last_knobs(const Failure& failure) {
  if (failure.kind == Failure::NoController)
    for (const LastKnob& knob : last_knobs_) {
      bool any = false;
      std::string story;
      for (const auto& [i, before] : knob.before) {
        const bool it_helped = helped(before, failure, i);
        any = any || it_helped;
        if (!it_helped) ++knob_misses_[i];
        const auto it = std::find(failure.agents.begin(), failure.agents.end(), i);
        const std::size_t w = static_cast<std::size_t>(it - failure.agents.begin());
        if (story.empty() && it != failure.agents.end() && w < failure.why.size())
          story = pb_.agents[i].name + ": " + miss_text(before) + " -> " + miss_text(failure.why[w]);
      }
      if (!any) unhelpful_[knob.name] = "its last use did not help enough (" + story + ")";
    }
  last_knobs_.clear();
}

std::vector<TrackerLever> Search::declared_levers(const Failure& failure) {
  // The failed agents' trackers' own knobs, as each declares them (no names in core).
  std::vector<TrackerLever> declared;
  for (int i : failure.agents) {
    std::vector<TrackerLever> mine;
    try {
      mine = instances_.get(pb_.agents[i].tracker)->levers(pb_.agents[i]);
    } catch (const std::exception&) {
    }
    for (const auto& l : mine)
      if (std::none_of(declared.begin(), declared.end(), [&](const TrackerLever& d) { return d.name == l.name; }))
        declared.push_back(l);
  }
  return declared;
}

bool Search::next_round(const Failure& failure, double elapsed, SearchRound& next, bool& replan) {
  SearchReport& rep = out_.search;
  rep.not_tried.clear();
  unfit_ = {};
  judge_last_knobs(failure);
  if (failure.kind == Failure::NoController && !failure.agents.empty()) return agents_round(failure, elapsed, next, replan);
  if (failure.kind == Failure::Plan && default_planner(failure, elapsed, next)) {
    replan = true;
    return true;
  }
  const std::vector<TrackerLever> declared = declared_levers(failure);
  for (const LeverChoice& lever : search::levers_for(failure, declared)) {
    search::Candidate c;
    if (!candidate(lever, failure, declared, elapsed, c)) continue;
    return take({c.proposal}, {search::lever_name(lever)}, failure, next, replan);
  }
  stop_without_lever(failure);
  return false;
}

std::string Search::best_untried(const Failure& failure) {
  // Every lever as if time were no object; their refusals go to the report's not_tried.
  const double any_time = -1e300;
  out_.search.not_tried.clear();
  std::vector<search::Candidate> best;
  std::vector<std::string> who;
  std::vector<Failure> each;
  if (failure.kind == Failure::NoController)
    for (std::size_t w = 0; w < failure.agents.size(); ++w) each.push_back(search::agent_failure(failure, w));
  else if (failure.kind == Failure::Plan || failure.kind == Failure::Certification)
    each.push_back(failure);
  for (const Failure& one : each) {
    const std::vector<search::Candidate> candidates = candidates_for(one, any_time);
    const int b = search::best_candidate(candidates);
    if (b < 0) continue;
    best.push_back(candidates[b]);
    who.push_back(one.kind == Failure::NoController ? pb_.agents[one.agents.front()].name + ": " : "");
  }
  if (best.empty()) return "";
  std::size_t k = 0;  // the agent whose lever is predicted slowest decides when all would be done
  for (std::size_t j = 1; j < best.size(); ++j)
    if (best[j].predicted_s > best[k].predicted_s) k = j;
  return "; the best lever untried: " + (best.size() > 1 ? who[k] : std::string()) + search::lever_name(best[k].lever) + " (about " +
         seconds(best[k].predicted_s) + (best.size() > 1 ? ", the slowest of " + std::to_string(best.size()) + " agents' levers" : "") + ")";
}

bool Search::resume(const std::string& dir, SearchRound& round) {
  namespace fs = std::filesystem;
  const std::string result_file = (fs::path(dir) / "result.json").string(), plan_file = (fs::path(dir) / "plan.json").string();
  if (!fs::exists(result_file) || !fs::exists(plan_file))
    throw ConfigError(dir, 0, 0, "--resume",
                      "expected a folder of an earlier `marsyn solve` of this problem with result.json and plan.json (a stopped "
                      "or failed solve that found a plan); " +
                          std::string(fs::exists(result_file) ? "plan.json" : "result.json") + " is missing");
  // The tubes the earlier search ended with: the controllers were made for them.
  nlohmann::json j;
  try {
    std::ifstream in(result_file);
    j = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw ConfigError(result_file, 0, 0, "", std::string("not readable as JSON: ") + e.what());
  }
  std::vector<AgentSpec> agents = pb_.agents;
  std::vector<char> same_start(agents.size(), 1);
  for (auto& a : agents) same_start[static_cast<std::size_t>(&a - agents.data())] = read_recorded_tube(j, result_file, a);
  std::swap(pb_.agents, agents);  // the plan is read and checked with the recorded tubes
  std::vector<NominalTrajectory> nominal;
  try {
    nominal = planning::read_plan_json(plan_file, pb_);
  } catch (...) {
    std::swap(pb_.agents, agents);
    throw;
  }
  GlobalPlan plan;
  plan.tau = pb_.tau;
  const int T = nominal.empty() ? 0 : static_cast<int>(nominal.front().u.size());
  for (int k = 0; k <= T; ++k) {
    Eigen::VectorXd x(pb_.product_state_dim()), u(pb_.product_input_dim());
    for (std::size_t i = 0, ox = 0, ou = 0; i < nominal.size(); ox += pb_.agents[i].n(), ou += pb_.agents[i].m(), ++i) {
      x.segment(ox, pb_.agents[i].n()) = nominal[i].x.at(k);
      if (k < T) u.segment(ou, pb_.agents[i].m()) = nominal[i].u.at(k);
    }
    plan.x.push_back(x);
    if (k < T) plan.u.push_back(u);
  }
  // A plan that starts elsewhere (x0 moved since) or tubes this problem no longer admits (an eps
  // not above a stated initial set's radius): not this problem's plan.
  for (std::size_t i = 0; i < nominal.size(); ++i) {
    const AgentSpec& a = pb_.agents[i];
    const std::string defect = agent_defect_text(a);
    if (nominal[i].x.empty() || nominal[i].x.front() != a.x0 || !defect.empty()) {
      const std::string why = !defect.empty() ? a.name + "'s recorded tube: " + defect : a.name + "'s plan starts elsewhere than x0";
      std::swap(pb_.agents, agents);
      log("[search] --resume " + dir + ": " + why + ": planning afresh");
      return false;
    }
  }
  const planning::MissionSchedule visits = planning::read_plan_visits(plan_file, pb_, T);
  const planning::RobustCheck check = T > 0 ? planning::check_robust(pb_, plan, visits) : planning::RobustCheck{};
  if (!check.passed) {
    std::swap(pb_.agents, agents);
    log("[search] --resume " + dir + ": its plan is not eps-robust for this problem (" + check.message + "): planning afresh");
    return false;
  }
  pb_.horizon = T;
  out_.plan = {};
  out_.plan.feasible = true;
  out_.plan.horizon = T;
  out_.plan.plan = plan;
  out_.plan.visits = visits;
  out_.plan.nominal = nominal;
  out_.plan.check = check;
  const auto controllers = read_agent_controllers(pb_, instances_, dir, true);
  const std::size_t N = pb_.agents.size();
  out_.agents.assign(N, {});
  tracked_params_.assign(N, "");
  tracked_nominal_ = nominal;
  const auto recorded = recorded_trackers(dir);
  int kept = 0;
  for (std::size_t i = 0; i < N; ++i) {
    out_.agents[i].name = pb_.agents[i].name;
    out_.agents[i].tracker = recorded.count(pb_.agents[i].name) ? recorded.at(pb_.agents[i].name) : pb_.agents[i].tracker.name;
    if (!controllers[i]) continue;
    if (!same_start[i]) {
      log("[search] --resume: " + pb_.agents[i].name +
          "'s controller was made for another initial set (x0_radius) or disturbance (W): tracked again");
      continue;
    }
    out_.agents[i].track.status = TrackerStatus::ControllerFound;
    out_.agents[i].track.controller = controllers[i];
    out_.agents[i].track.message = "kept from " + dir + " (--resume)";
    tracked_params_[i] = agent_parameters(pb_.agents[i]);
    ++kept;
  }
  round.action = "resumed from " + dir + ": its plan (T = " + std::to_string(T) + ") and " + std::to_string(kept) + " controller" +
                 (kept == 1 ? "" : "s");
  round.horizon = T;
  log("[search] " + round.action + "; the plan is eps-robust with the recorded tubes (smallest margin " +
      number_text(check.min_margin, 3) + "); tracking the other " + std::to_string(N - kept) + " agent(s)");
  return true;
}

bool Search::default_planner(const Failure& failure, double elapsed, SearchRound& next) {
  // A planner the file names that finds no plan at any horizon is not the end: the default
  // planner once, before the horizon and eps levers (a doorway that Ipopt failed at every
  // horizon verified with altro in 3 s). Crowded starts and goals without room fail for every
  // planner: no point trying another.
  const std::string name = std::string("plan with the default planner (") + kDefaultPlanner + ")";
  if (pb_.planner.name == kDefaultPlanner || !loaded_.registry || !loaded_.registry->find("planner", kDefaultPlanner)) return false;
  if (failure.start_eps_factor < 1 || failure.goal_eps_factor < 1 || failure.formation_eps_factor < 1) return false;
  if (!loaded_.planner_fallback) {
    out_.search.not_tried.push_back({name, "search: {planner_fallback: false}"});
    return false;
  }
  const double need = last_plan_s_ + last_track_s_ + last_certify_s_, left = opt_.time_limit_s - elapsed;
  if (!rank0_says(need <= left)) {
    if (unfit_.s < 0 || need < unfit_.s) unfit_ = {name, need};
    out_.search.not_tried.push_back({name, "would take about " + seconds(need) + ", " + seconds(std::max(0.0, left)) + " left"});
    return false;
  }
  next.action = name;
  next.reason = failure.reason;
  next.changes = {{"", "planner", pb_.planner.name, kDefaultPlanner}};
  pb_.planner = PluginChoice{kDefaultPlanner, {}};
  pb_.warm_start_planner = {};
  log("[search] round " + std::to_string(next.index) + ": " + failure.reason + "; " + name + " (the file's planner, " +
      next.changes.front().from + ", found no eps-robust plan at any horizon; search: {planner_fallback: false} turns this off)");
  return true;
}

bool Search::candidate(const LeverChoice& lever, const Failure& failure, const std::vector<TrackerLever>& declared,
                       double elapsed, search::Candidate& out) {
  SearchReport& rep = out_.search;
  const std::string name = search::lever_name(lever);
  auto refuse = [&](const std::string& why) {
    const std::string who = multi_agent_ && failure.agents.size() == 1 ? pb_.agents[failure.agents.front()].name + ": " : "";
    for (const auto& n : rep.not_tried)
      if (n.lever == name && n.why == who + why) return false;
    rep.not_tried.push_back({name, who + why});
    return false;
  };
  if (unhelpful_.count(name)) return refuse(unhelpful_.at(name));
  // A wider tube is counted per agent: misses move between coordinates (a drone's vx, then vy)
  // and each agent's tube is its own; the other levers count per search, as before.
  const bool own = lever.lever == Lever::WidenForMiss && failure.agents.size() == 1;
  const int used = uses_[own ? uses_key(name, failure.agents.front()) : name];
  if (used >= search::lever_cap(lever.lever))
    return refuse("used " + std::to_string(used) + " times" + (own ? " for this agent" : "") + ", its limit");
  search::Proposal p = search::propose(lever, failure, team(), instances_, ask(), used);
  if (!p.why_not.empty()) return refuse(p.why_not);
  if (seen_.count(search::fingerprint(p.agents, p.extra, p.input_share, p.min_horizon)))
    return refuse("it would repeat an attempt already made");
  double cost = 1;
  for (const auto& d : declared)
    if (lever.lever == Lever::TrackerLever && d.name == lever.tracker_lever) cost = d.cost_factor;
  const double need = estimate(p, cost), left = opt_.time_limit_s - elapsed;
  if (!rank0_says(need <= left)) {
    if (unfit_.s < 0 || need < unfit_.s) unfit_ = {name, need};
    return refuse("would take about " + seconds(need) + ", " + seconds(std::max(0.0, left)) + " left");
  }
  out = {lever, std::move(p), need};
  return true;
}

std::vector<search::Candidate> Search::candidates_for(const Failure& failure, double elapsed) {
  const std::vector<TrackerLever> declared = declared_levers(failure);
  std::vector<search::Candidate> out;
  for (const LeverChoice& lever : search::levers_for(failure, declared)) {
    search::Candidate c;
    if (candidate(lever, failure, declared, elapsed, c)) out.push_back(std::move(c));
  }
  return out;
}

bool Search::agents_round(const Failure& failure, double elapsed, SearchRound& next, bool& replan) {
  // Each failed agent its own lever (search_rank.hpp): a cheap fix for one agent never waits
  // behind an expensive one for another, and one agent's reason no longer decides for all.
  multi_agent_ = failure.agents.size() > 1;
  std::vector<search::Proposal> picks;
  std::vector<std::string> names, who;
  std::vector<std::vector<search::Candidate>> all(failure.agents.size());
  std::vector<int> bests(failure.agents.size(), -1);
  for (std::size_t w = 0; w < failure.agents.size(); ++w) {
    all[w] = candidates_for(search::agent_failure(failure, w), elapsed);
    bests[w] = first_choice(all[w], failure.agents[w]);
  }
  const std::set<int> wider_ok = wider_tubes_keep_plan(failure, all, bests);
  for (std::size_t w = 0; w < failure.agents.size(); ++w) {
    std::vector<search::Candidate>& candidates = all[w];
    int best = bests[w];
    if (best < 0) continue;
    if (candidates[best].proposal.recheck && candidates.size() > 1 && !wider_ok.count(failure.agents[w])) {
      // A wider tube for this agent: checked now, so that a re-plan it would need (every agent
      // tracked again) is weighed against this agent's levers that keep the plan. The plan's end
      // is read first: where it sits on the edge of the goal shrunk by the new eps, the exact
      // check (a second or more for 400 agents) cannot pass.
      planning::RobustCheck c;
      const int i = failure.agents[w];
      c.message = goal_conflict(candidates[best].proposal.agents[static_cast<std::size_t>(i)], i);
      if (!c.message.empty() || !robust_with(candidates[best].proposal.agents, c)) {
        search::Candidate& wide = candidates[best];
        wide.proposal.recheck = false;
        wide.predicted_s = last_plan_s_ + std::max(last_track_s_, full_track_s_) + last_certify_s_;
        // The best of the levers after it that keep the plan (a slow knob still waits behind
        // another tracker), when it is predicted faster than the re-plan.
        std::vector<search::Candidate> keep;
        std::vector<int> at;
        for (std::size_t k = static_cast<std::size_t>(best) + 1; k < candidates.size(); ++k)
          if (!candidates[k].proposal.replan) {
            keep.push_back(candidates[k]);
            at.push_back(static_cast<int>(k));
          }
        const int alt = fallback_over_knob(keep, search::best_candidate(keep), failure.agents[w]);
        if (alt >= 0 && keep[alt].predicted_s < wide.predicted_s) {
          log("[search] " + pb_.agents[failure.agents[w]].name + ": the plan is not eps-robust with the wider tube (" + c.message +
              "): " + search::lever_name(keep[alt].lever) + " first (about " + seconds(keep[alt].predicted_s) +
              "; a re-plan about " + seconds(wide.predicted_s) + ")");
          best = at[alt];
        }
      }
    }
    if (best > 0 && candidates[best].lever.lever == Lever::FallBack && candidates[0].lever.lever == Lever::TrackerLever) {
      // Say why when the prediction alone would have taken the knob.
      const int misses = knob_misses_[failure.agents[w]];
      const std::string why = candidates[best].predicted_s > candidates[0].predicted_s && misses > 0
                                  ? ": the tracker's own knobs did not help it " + std::to_string(misses) + (misses == 1 ? " time" : " times")
                                  : "";
      log("[search] " + pb_.agents[failure.agents[w]].name + ": " + search::lever_name(candidates[best].lever) + " (about " +
          seconds(candidates[best].predicted_s) + ") before " + search::lever_name(candidates[0].lever) + " (about " +
          seconds(candidates[0].predicted_s) + ")" + why);
    }
    picks.push_back(std::move(candidates[best].proposal));
    names.push_back(search::lever_name(candidates[best].lever));
    who.push_back(pb_.agents[failure.agents[w]].name);
  }
  multi_agent_ = false;
  if (picks.empty()) {
    stop_without_lever(failure);
    return false;
  }
  // An agent with no lever left keeps failing; the others' levers still run: its failure is
  // reported in the next round's outcome, and the search stops when nothing is left for anyone.
  return take(picks, names, failure, next, replan, who);
}

int Search::fallback_over_knob(const std::vector<search::Candidate>& candidates, int best, int agent) {
  // A knob after knobs that did not help: another tracker first, whatever the predictions say.
  if (best >= 0 && candidates[static_cast<std::size_t>(best)].lever.lever == Lever::TrackerLever &&
      knob_misses_[agent] >= kKnobsBeforeFallback)
    for (std::size_t k = 0; k < candidates.size(); ++k)
      if (candidates[k].lever.lever == Lever::FallBack) return static_cast<int>(k);
  return best;
}

int Search::first_choice(const std::vector<search::Candidate>& candidates, int agent) {
  int best = search::best_candidate(candidates);
  if (best < 0) return best;
  // Twice wider and still missing by a little: the misses move rather than close (a 12-state
  // drone's vx, then vy, then vx again, as the wider tube softens its feedback); the tracker's
  // own knob that keeps the plan goes first now, the wider tube after it.
  if (candidates[best].lever.lever == Lever::WidenForMiss &&
      uses_[uses_key(search::lever_name(candidates[best].lever), agent)] >= kWidenBeforeKnobs) {
    std::vector<search::Candidate> rest;
    std::vector<int> at;
    for (std::size_t k = 0; k < candidates.size(); ++k)
      if (static_cast<int>(k) != best && !candidates[k].proposal.replan) {
        rest.push_back(candidates[k]);
        at.push_back(static_cast<int>(k));
      }
    if (const int alt = search::best_candidate(rest); alt >= 0) best = at[alt];
  }
  return fallback_over_knob(candidates, best, agent);
}

std::set<int> Search::wider_tubes_keep_plan(const Failure& failure, const std::vector<std::vector<search::Candidate>>& all,
                                            const std::vector<int>& bests) {
  // Every agent's wider tube in one exact check: margins only fall as tubes widen, so a plan
  // robust with all of them is robust with each alone. 30 agents of the 400-robot field missing
  // by a little cost one check (about 1.5 s) instead of one each; when it fails, each agent is
  // checked alone as before.
  std::vector<AgentSpec> team = pb_.agents;
  std::set<int> wider;
  for (std::size_t w = 0; w < failure.agents.size(); ++w) {
    const int best = bests[w];
    if (best < 0 || all[w].size() < 2 || !all[w][static_cast<std::size_t>(best)].proposal.recheck) continue;
    const search::Proposal& p = all[w][static_cast<std::size_t>(best)].proposal;
    const int i = failure.agents[w];
    if (!goal_conflict(p.agents[static_cast<std::size_t>(i)], i).empty()) continue;
    for (int j : p.changed) team[static_cast<std::size_t>(j)] = p.agents[static_cast<std::size_t>(j)];
    wider.insert(i);
  }
  planning::RobustCheck c;
  if (wider.size() < 2 || !robust_with(team, c)) return {};
  std::string names;
  int listed = 0;
  for (int i : wider)
    if (listed++ < 4) names += (names.empty() ? "" : ", ") + pb_.agents[static_cast<std::size_t>(i)].name;
  if (listed > 4) names += " and " + std::to_string(listed - 4) + " more";
  char margin[64];
  std::snprintf(margin, sizeof margin, "%.3g", c.min_margin);
  log("[search] the plan is eps-robust with the wider tubes of " + std::to_string(wider.size()) + " agents at once (" + names +
      "; smallest margin " + margin + ")");
  return wider;
}

void Search::stop_without_lever(const Failure& failure) {
  SearchReport& rep = out_.search;
  rep.stop_reason = rep.not_tried.empty() ? "no lever addresses " + failure.reason : failure.reason + "; no lever left";
  if (failure.kind == Failure::Plan && failure.beyond_eps && !failure.horizon_blocked.empty())
    rep.stop_reason = failure.reason + "; a narrower tube cannot close a shortfall of more than twice the largest eps, "
                                       "so the search has no lever to try";
  // The time limit names the best lever it kept from running (the cheapest that did not fit).
  if (unfit_.s >= 0)
    rep.stop_reason = failure.reason + "; no lever left fits the time left of the limit (" + seconds(opt_.time_limit_s) +
                      "): the best, " + unfit_.lever + ", would take about " + seconds(unfit_.s);
}

bool Search::take(const std::vector<search::Proposal>& picks, const std::vector<std::string>& names, const Failure& failure,
                  SearchRound& next, bool& replan, const std::vector<std::string>& who) {
  search::Proposal p = picks.size() == 1 ? picks.front() : search::merge(picks, team());
  if (picks.size() > 1 && seen_.count(search::fingerprint(p.agents, p.extra, p.input_share, p.min_horizon))) {
    out_.search.not_tried.push_back({search::merged_action(names, who), "it would repeat an attempt already made"});
    stop_without_lever(failure);
    return false;
  }
  for (std::size_t k = 0; k < picks.size(); ++k)
    if (picks[k].lever.lever == Lever::TrackerLever) remember_knob(names[k], picks[k], failure);
  const std::string action = search::merged_action(names, who);
  const std::vector<SearchChange> before_changes = p.changes;
  // The round before the lever, to go back to when a re-plan it calls for finds no plan.
  Saved before;
  if (p.replan && failure.kind == Failure::NoController) before = snapshot(next.index - 1);
  search::apply(p, team());
  std::string kept;
  if (p.replan && p.recheck && failure.kind == Failure::NoController && keeps_plan(kept)) p.replan = false;
  replan_base_.active = p.replan && failure.kind == Failure::NoController;
  if (replan_base_.active) {
    std::vector<std::string> replanning;
    for (std::size_t k = 0; k < picks.size(); ++k)
      if (picks[k].replan) replanning.push_back(names[k]);
    replan_base_ = {true, replanning, failure, std::move(before)};
  }
  // A re-plan after a tracker failure starts from the plan it replaces.
  warm_from_last_ = p.replan && failure.kind == Failure::NoController;
  std::set<std::string> counted;
  for (std::size_t k = 0; k < picks.size(); ++k) {
    const bool own = picks[k].lever.lever == Lever::WidenForMiss;
    for (int i : own ? picks[k].changed : std::vector<int>{-1})
      if (const std::string key = i >= 0 ? uses_key(names[k], i) : names[k]; counted.insert(key).second) ++uses_[key];
  }
  next.action = action;
  next.reason = failure.reason;
  next.changes = before_changes;
  replan = p.replan;
  // Announced only now that it runs.
  log("[search] round " + std::to_string(next.index) + ": " + failure.reason + "; " + action + " (" +
      changes_text(grouped(before_changes, pb_.agents.size())) + ")" + (p.replan ? "; re-planning" : "; tracking again with the same plan"));
  if (!kept.empty()) log("[search] " + kept);  // what the re-check of the plan found
  return true;
}

bool Search::keeps_plan(std::string& said) {
  // Wider tubes only: the plan stays when the exact check passes with them (docs/search.md).
  planning::RobustCheck c;
  const bool passed = robust_with(pb_.agents, c);
  if (passed && root()) out_.plan.check = c;
  char buf[160];
  std::snprintf(buf, sizeof buf, "the plan is still eps-robust with the wider tube (smallest margin %.3g): no re-plan", c.min_margin);
  said = buf;
  if (!passed) said = "the plan is not eps-robust with the wider tube (" + c.message + "): re-planning";
  return passed;
}

std::string Search::goal_conflict(const AgentSpec& a, int i) const {
  const auto at = static_cast<std::size_t>(i);
  if (at >= out_.plan.nominal.size() || out_.plan.nominal[at].x.empty() || a.goal.dim() != a.n()) return "";
  const Eigen::VectorXd& x = out_.plan.nominal[at].x.back();
  const auto names = a.dynamics ? a.dynamics->state_names() : std::vector<std::string>{};
  for (int c = 0; c < a.n() && c < x.size(); ++c) {
    const double room = std::min(x[c] - (a.goal.lo[c] + a.tube.eps[c]), (a.goal.hi[c] - a.tube.eps[c]) - x[c]);
    if (room < 0)
      return "the plan ends " + number_text(-room, 3) + " outside the goal of " + a.name + " shrunk by the wider tube in " +
             (c < static_cast<int>(names.size()) ? names[c] : "x" + std::to_string(c));
  }
  return "";
}

bool Search::robust_with(const std::vector<AgentSpec>& agents, planning::RobustCheck& c) {
  if (!rank0_says(out_.plan.feasible && !out_.plan.plan.u.empty())) return false;
  const Stopwatch t;
  if (root()) {
    // The U the plan was made for (tightened where the search tightened it), with these tubes.
    Problem checked;
    if (!tighten_inputs(agents, checked)) {
      checked = pb_;
      checked.agents = agents;
    }
    c = planning::check_robust(checked, out_.plan.plan, out_.plan.visits);
  }
  last_check_s_ = t.seconds();
  return rank0_says(c.passed);
}

void Search::remember_knob(const std::string& name, const search::Proposal& p, const Failure& failure) {
  auto it = std::find_if(last_knobs_.begin(), last_knobs_.end(), [&](const LastKnob& k) { return k.name == name; });
  if (it == last_knobs_.end()) it = last_knobs_.insert(last_knobs_.end(), LastKnob{name, {}});
  for (int i : p.changed) {
    const auto at = std::find(failure.agents.begin(), failure.agents.end(), i);
    const std::size_t w = static_cast<std::size_t>(at - failure.agents.begin());
    if (at != failure.agents.end() && w < failure.why.size()) it->before[i] = failure.why[w];
  }
}

bool Search::narrow_auto_eps(double elapsed, SearchRound& next) {
  if (auto_rounds_ >= kAutoEpsIterations || loaded_.auto_tube.size() != pb_.agents.size()) return false;
  std::vector<AgentSpec> agents = pb_.agents;
  std::vector<SearchChange> changes;
  for (std::size_t i = 0; i < agents.size(); ++i) {
    const AutoTube& at = loaded_.auto_tube[i];
    if (!at.eps || i >= out_.agents.size() || !out_.agents[i].track.controller || i >= out_.plan.nominal.size()) continue;
    const Eigen::VectorXd kept = search::kept_tube(out_.agents[i].track, out_.plan.nominal[i], pb_.tau);
    const Eigen::VectorXd eps = search::narrower_auto_eps(agents[i], kept, pb_.tau, loaded_.problem.agents[i].tube.eps);
    if (!eps.size()) continue;
    AgentSpec b = agents[i];
    b.tube.eps = eps;
    follow_tube(instances_, b, TubeChange::Set);  // the automatic fields (abcd's grid) follow eps
    if (!agent_consistent(b) || !assess_tracker(instances_, b.tracker, b, ask()).ok) continue;
    search::describe(agents[i], b, changes);  // eps and the automatic fields that follow it
    out_.auto_notes.resize(pb_.agents.size());
    out_.auto_notes[i] += (out_.auto_notes[i].empty() ? "" : "; ") + std::string("round ") + std::to_string(next.index - 1) +
                          "'s controller kept " + search::vector_text(kept) + " at the samples: eps " +
                          search::vector_text(eps) + " (" +
                          search::auto_eps_rule_text(agents[i], kept, pb_.tau, loaded_.problem.agents[i].tube.eps, eps,
                                                     agents[i].dynamics ? agents[i].dynamics->state_names() : std::vector<std::string>{}) +
                          ")";
    agents[i] = b;
  }
  if (changes.empty() || seen_.count(search::fingerprint(agents, extra_, input_share_, min_horizon_))) return false;
  const double need = last_plan_s_ + last_track_s_ + last_certify_s_, left = opt_.time_limit_s - elapsed;
  if (!rank0_says(need <= left)) return false;
  saved_ = snapshot(next.index - 1);
  pb_.agents = agents;
  ++auto_rounds_;
  trial_ = true;
  next.action = "narrow the auto eps to the tube kept + " + std::to_string(static_cast<int>(100 * kAutoEpsMargin)) + " %";
  next.reason = "every agent has a controller; eps: auto";
  next.changes = changes;
  log("[search] round " + std::to_string(next.index) + ": " + next.reason + "; " + next.action + " (" +
      changes_text(grouped(changes, pb_.agents.size())) + "); re-planning");
  return true;
}

Search::Saved Search::snapshot(int round) const {
  return {out_.plan, out_.agents, out_.certification, out_.certification_ran, pb_.agents, out_.trackers, extra_,
          input_share_, min_horizon_, pb_.horizon, round};
}

void Search::restore(const Saved& s) {
  out_.plan = s.plan;
  out_.agents = s.agents;
  out_.certification = s.certification;
  out_.certification_ran = s.certification_ran;
  pb_.agents = s.specs;
  out_.trackers = s.trackers;
  extra_ = s.extra;
  input_share_ = s.input_share;
  min_horizon_ = s.min_horizon;
  pb_.horizon = s.horizon;
  out_.failure.clear();
}

bool Search::run(const Stopwatch& t_start) {
  SearchReport& rep = out_.search;
  SearchRound round;
  round.action = "first attempt";
  Stopwatch t_round;
  bool replan = true, done = false;
  if (!opt_.resume_dir.empty()) {
    if (opt_.cluster && opt_.cluster->size() > 1)
      throw ConfigError("command line", 0, 0, "--resume", "not over MPI yet: resume in one process");
    replan = !resume(opt_.resume_dir, round);
  }
  for (;;) {
    seen_.insert(fingerprint());
    Failure f;
    if (stopping()) {
      rep.stop_reason = cause_text() + " before round " + std::to_string(rep.rounds.size() + 1);
      rep.interrupted = true;
      break;
    }
    if (replan) f = plan(round, opt_.time_limit_s - t_start.seconds());
    bool back = false;  // this round's re-plan failed: the search resumes from the round before it
    if (replan && replan_base_.active) {
      if (f.kind == Failure::Plan) {
        const ReplanBase base = std::move(replan_base_);
        std::string levers;
        std::set<std::string> said;  // one lever taken by four agents is named once, not four times
        for (const auto& l : base.levers) {
          unhelpful_[l] = "its re-plan found no eps-robust plan (" + f.reason + ")";
          if (said.insert(l).second) levers += (levers.empty() ? "" : " and ") + l;
        }
        log("[search] " + levers + " left no eps-robust plan; back to round " + std::to_string(base.saved.round) +
            "'s plan and its failure (" + base.failure.reason + ")");
        restore(base.saved);
        f = base.failure;
        back = true;
      }
      replan_base_.active = false;
    }
    round.horizon = out_.plan.horizon;
    if (f.kind == Failure::None) f = track(round);
    if (f.kind == Failure::None && pb_.guarantee == Guarantee::Continuous) f = certify(round);
    round.outcome = f.kind == Failure::None ? "every agent has a controller" : f.reason;
    if (back) round.outcome = "no eps-robust plan with " + round.action + "; back to the plan before it (" + f.reason + ")";
    round.time_s = t_round.seconds();
    rep.plan_time_s += round.plan_time_s;
    rep.track_time_s += round.track_time_s;
    rep.certify_time_s += round.certify_time_s;
    const std::size_t index = rep.rounds.size() + 1;
    rep.rounds.push_back(round);
    out_.failure = f.kind == Failure::None ? "" : f.reason;
    const std::string success = pb_.guarantee == Guarantee::Continuous ? "every agent has a controller, certified"
                                                                         : "every agent has a controller";
    if (f.kind == Failure::None) {
      trial_ = false;
      SearchRound next;
      next.index = static_cast<int>(index) + 1;
      t_round = Stopwatch();
      if (index < static_cast<std::size_t>(opt_.max_rounds) && narrow_auto_eps(t_start.seconds(), next)) {
        round = next;
        replan = true;
        continue;
      }
      rep.stop_reason = success;
      done = true;
      break;
    }
    if (trial_) {
      // The narrower auto eps did not verify: the last verified round stands.
      restore(saved_);
      rep.stop_reason = success + " (round " + std::to_string(saved_.round) + "'s; the narrower auto eps of round " +
                        std::to_string(index) + " failed: " + f.reason + ")";
      // Its changes and the notes that proposed them no longer describe the result.
      for (auto& r : rep.rounds)
        if (r.index > saved_.round) r.undone = true;
      for (auto& note : out_.auto_notes)
        if (!note.empty()) note += "; round " + std::to_string(index) + " failed with it, round " + std::to_string(saved_.round) + "'s eps stands";
      done = true;
      break;
    }
    t_round = Stopwatch();  // deciding on the next round is part of it
    if (stopping()) {
      rep.stop_reason = cause_text() + " in round " + std::to_string(index) + " (" + f.reason + ")" + best_untried(f);
      rep.interrupted = true;
      break;
    }
    if (index >= static_cast<std::size_t>(opt_.max_rounds)) {
      rep.stop_reason = f.reason + "; the round limit (" + std::to_string(opt_.max_rounds) + ") is reached";
      break;
    }
    SearchRound next;
    next.index = static_cast<int>(index) + 1;
    if (!next_round(f, t_start.seconds(), next, replan)) break;
    round = next;
  }
  rep.time_s = t_start.seconds();
  return done;
}

// Each agent's tracker (AgentSpec::tracker, resolved by the loader). An agent without one (a
// Problem built by hand) gets the top-level tracker, or the first installed one (the registry's
// order: by library name within a folder).
void resolve_trackers(const LoadedProblem& loaded, SolveOutcome& out) {
  Problem& pb = out.problem;
  std::string first;
  if (loaded.registry)
    if (const auto names = loaded.registry->names(PluginKind<Tracker>::name); !names.empty()) first = names.front();
  for (auto& a : pb.agents)
    if (a.tracker.name.empty())
      a.tracker = pb.tracker.name.empty() || pb.tracker.name == kAutoTracker ? PluginChoice{first, {}} : pb.tracker;
  out.trackers = loaded.trackers;
  out.trackers.resize(pb.agents.size());
}

// Stage 5 on the search's controllers, recorded in `out`.
void verify_controllers(Setup& setup, const SolveOptions& opt, SolveOutcome& out) {
  VerificationOptions vo;
  vo.runs = opt.verification_runs;
  vo.threads = opt.threads;
  vo.collective = opt.cluster;
  // A live bar on a terminal (runs, runs/s, time left), else a line every quarter.
  vo.progress = [p = std::make_shared<RunProgress>(opt.log, opt.live)](int done, int total) { (*p)(done, total); };
  // The runs judge the stages (and the staged obstacles' windows) at the plan's visit knots.
  {
    out.memory.verify_predicted_bytes = verification_memory_bytes(out.problem, vo.fine_substeps);
    const StageWatch watch(out.memory.verify);
    out.verification = setup.verify(planning::with_visits(out.problem, out.plan.visits), out.plan.nominal,
                                    controllers_of(out.agents), vo);
  }
  out.verification_ran = true;
  out.attempts.push_back({"verify", std::to_string(out.verification.runs) + " runs",
                          std::to_string(out.verification.violations) + " violations", out.verification.time_s,
                          out.problem.horizon});
  out.verified = out.verification.violations == 0 && out.verification.tube_violations == 0;
  // A closed-loop run cannot certify; it can only refute. "verified" rests on the trackers'
  // guarantee (and, in continuous time, on the certificate above).
  out.failure = out.verified ? "" : "verification found violations (a soundness bug): " + out.verification.worst;
}

}  // namespace

SolveOutcome Setup::solve(const SolveOptions& opt) {
  const Stopwatch t_start;
  SolveOutcome out;
  out.problem = problem();
  auto log = [&](const std::string& s) {
    if (opt.log) opt.log(s);
  };
  resolve_trackers(loaded(), out);

  Search search(*this, opt, out);
  const bool controllers = search.run(t_start);
  log("[search] " + out.search.message());
  if (out.search.interrupted) {
    // What was found so far goes to disk as it is (status stopped); nothing more is started.
    out.failure = out.search.stop_reason;
    out.global.status = "not attempted: the search was stopped";
    out.total_time_s = t_start.seconds();
    return out;
  }

  // The baseline is a figure for the report: rank 0's alone.
  if (!opt.cluster || opt.cluster->rank() == 0) out.global = global_baseline(out.problem, opt, log);
  if (out.global.attempted)
    out.attempts.push_back({"global ABCD", kGlobalAbcdParameters, out.global.status, out.global.time_s, 0});

  if (controllers) verify_controllers(*this, opt, out);
  // `check`'s figure is the planner's at the file's horizon: beside the peak only when that is
  // the horizon planned.
  if (out.problem.horizon == problem().horizon) out.memory.plan_predicted_bytes = loaded().plan_memory.bytes;
  out.memory.track_predicted_bytes = tracking_memory(out.trackers, opt.threads, problem().horizon, out.problem.horizon).bytes();
  out.total_time_s = t_start.seconds();
  return out;
}

SolveOutcome solve(const LoadedProblem& loaded, const SolveOptions& opt) { return Setup(loaded).solve(opt); }

}  // namespace marsyn
