#include "marsyn/core/solve.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "marsyn/core/stopwatch.hpp"
#include "marsyn/core/verification/run_progress.hpp"
#include "marsyn/core/tracking/global_abcd.hpp"
#include "marsyn/core/tracking/mpi_plan_broadcast.hpp"
#include "marsyn/core/tracking/track_agents.hpp"
#include "marsyn/core/search_levers.hpp"

namespace marsyn {
namespace {

using search::Failure;
using search::Lever;

// An attempt's parameters for one agent: its tracker, eps, and the grids when it has them.
std::string agent_parameters(const AgentSpec& a) {
  std::string p = "tracker=" + a.tracker.name + " eps=" + search::vector_text(a.tube.eps);
  if (a.tube.eta_x.size()) p += " eta_x=" + search::vector_text(a.tube.eta_x);
  if (a.tube.eta_u.size()) p += " eta_u=" + search::vector_text(a.tube.eta_u);
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
  Search(const LoadedProblem& loaded, const SolveOptions& opt, SolveOutcome& out)
      : loaded_(loaded), opt_(opt), out_(out), pb_(out.problem), instances_(loaded.registry) {
    planner_ = loaded.registry->create<Planner>(pb_.planner.name, pb_.planner.params);
    if (!pb_.warm_start_planner.name.empty())
      warm_planner_ = loaded.registry->create<Planner>(pb_.warm_start_planner.name, pb_.warm_start_planner.params);
    out_.search.time_limit_s = opt.time_limit_s;
  }

  // Runs rounds until every agent has a certified controller or the search stops; returns
  // whether the last round left every agent with a controller (certified when continuous).
  bool run(const Stopwatch& t_start);

 private:
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
  AssessRequest ask() const { return {pb_.horizon, pb_.tau, loaded_.memory_budget}; }

  Failure plan(SearchRound& round, double time_left);
  Failure track(SearchRound& round);
  Failure certify(SearchRound& round);
  // The next round's lever, applied (replan: whether it invalidated the plan), or false (with
  // stop_reason and not_tried set).
  bool next_round(const Failure& failure, double elapsed, SearchRound& next, bool& replan);
  // Seconds the round a proposal asks for would take, from the last rounds' times.
  double estimate(const search::Proposal& p);

  const LoadedProblem& loaded_;
  const SolveOptions& opt_;
  SolveOutcome& out_;
  Problem& pb_;
  TrackerInstances instances_;
  std::shared_ptr<Planner> planner_, warm_planner_;
  std::map<std::string, double> extra_;  // per constraint: grows where certification fell short
  std::set<std::string> seen_;           // fingerprints of the attempts made
  int uses_[search::kLeverCount] = {};
  double last_plan_s_ = 0, last_track_s_ = 0, last_certify_s_ = 0;
};

Failure Search::plan(SearchRound& round, double time_left) {
  planning::PlanSearchOptions po;
  po.time_limit_s = std::max(1.0, time_left);
  po.log = [&](const std::string& s) { log("[plan] " + s); };
  po.warm_start_planner = warm_planner_.get();
  po.assembly.extra = extra_;
  log("[plan] " + pb_.planner.name + " on the product system (" + std::to_string(pb_.product_state_dim()) + " state" +
      (pb_.product_state_dim() == 1 ? "" : "s") + ", " + std::to_string(pb_.product_input_dim()) + " input" +
      (pb_.product_input_dim() == 1 ? "" : "s") + ")");
  const Stopwatch t;
  if (root()) out_.plan = planning::plan(pb_, *planner_, po);
  if (opt_.cluster) mpi::broadcast_plan(*opt_.cluster, out_.plan);  // what the other ranks need of it
  round.planned = true;
  round.plan_time_s = last_plan_s_ = t.seconds();
  // Each horizon the planning stage tried, with its own T.
  for (const auto& pa : out_.plan.attempts) {
    std::ostringstream params;
    params << "planner=" << pa.planner << " T=" << pa.horizon;
    if (!extra_.empty()) params << " extra clearance for " << extra_.size() << " constraint(s)";
    for (const auto& a : pb_.agents) params << " eps[" << a.name << "]=" << search::vector_text(a.tube.eps);
    const bool robust = pa.check.passed;
    out_.attempts.push_back({"plan", params.str(),
                             robust ? "feasible, smallest robust margin " + std::to_string(pa.check.min_margin)
                                    : std::string(to_string(pa.status)) + (pa.check.message.empty() ? "" : ": " + pa.check.message),
                             pa.solve_time_s, pa.horizon});
  }
  round.horizon = out_.plan.horizon;
  if (!out_.plan.feasible) return {Failure::Plan, "planning failed: " + out_.plan.check.message, {}, {}};
  if (!out_.plan.nominal.empty()) pb_.horizon = out_.plan.horizon;
  extra_ = out_.plan.extra;  // a later re-plan keeps the clearance this one needed
  return {};
}

Failure Search::track(SearchRound& round) {
  const Stopwatch t;
  out_.agents = track_agents(pb_, out_.plan.nominal, instances_.for_agents(pb_), opt_, loaded_.memory_budget);
  round.track_time_s = last_track_s_ = t.seconds();
  log("[track] all agents in " + std::to_string(round.track_time_s) + " s");
  Failure f{Failure::NoController, "no controller for", {}, {}};
  for (std::size_t i = 0; i < out_.agents.size(); ++i) {
    const auto& r = out_.agents[i].track;
    out_.attempts.push_back({"track " + out_.agents[i].name, agent_parameters(pb_.agents[i]),
                             std::string(to_string(r.status)) + (r.message.empty() ? "" : ": " + r.message),
                             r.stats.abstraction_time_s + r.stats.synthesis_time_s, pb_.horizon});
    if (r.status == TrackerStatus::ControllerFound) continue;
    // Only "no controller" is a reason to change parameters; bad input or an exhausted budget
    // would fail the same way again.
    if (r.status != TrackerStatus::NoController)
      return {Failure::Unsearchable,
              "tracking " + pb_.agents[i].name + ": " + to_string(r.status) + (r.message.empty() ? "" : ": " + r.message),
              {}, {}};
    f.agents.push_back(static_cast<int>(i));
    f.reason += " " + pb_.agents[i].name;
  }
  return f.agents.empty() ? Failure{} : f;
}

Failure Search::certify(SearchRound& round) {
  std::vector<std::shared_ptr<const Controller>> ctrls;
  for (const auto& a : out_.agents) ctrls.push_back(a.track.controller);
  out_.certification = marsyn::certify(pb_, ctrls);
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

double Search::estimate(const search::Proposal& p) {
  // Tracking scales with the trackers' own work estimates (a finer grid costs more).
  double ratio = 1;
  for (int i : p.changed) {
    const double before = assess_tracker(instances_, pb_.agents[i].tracker, pb_.agents[i], ask()).work_s;
    const double after = assess_tracker(instances_, p.agents[i].tracker, p.agents[i], ask()).work_s;
    if (before > 0 && after > 0) ratio = std::max(ratio, after / before);
  }
  return (p.replan ? last_plan_s_ : 0) + last_track_s_ * ratio + last_certify_s_;
}

bool Search::next_round(const Failure& failure, double elapsed, SearchRound& next, bool& replan) {
  SearchReport& rep = out_.search;
  rep.not_tried.clear();
  const search::Team team{&pb_, &out_.trackers, &extra_};
  for (const Lever lever : search::levers_for(failure)) {
    const std::string name = search::lever_name(lever);
    const int k = static_cast<int>(lever);
    if (uses_[k] >= search::lever_cap(lever)) {
      rep.not_tried.push_back({name, "used " + std::to_string(uses_[k]) + " times, its limit"});
      continue;
    }
    const search::Proposal p = search::propose(lever, failure, team, instances_, ask());
    if (!p.why_not.empty()) {
      rep.not_tried.push_back({name, p.why_not});
      continue;
    }
    if (seen_.count(search::fingerprint(p.agents, p.extra))) {
      rep.not_tried.push_back({name, "it would repeat an attempt already made"});
      continue;
    }
    const double need = estimate(p), left = opt_.time_limit_s - elapsed;
    if (!rank0_says(need <= left)) {
      rep.not_tried.push_back({name, "would take about " + seconds(need) + ", " + seconds(std::max(0.0, left)) + " left"});
      continue;
    }
    search::apply(p, team);
    ++uses_[k];
    next.action = name;
    next.reason = failure.reason;
    next.changes = p.changes;
    replan = p.replan;
    // Announced only now that it runs.
    log("[search] round " + std::to_string(next.index) + ": " + failure.reason + "; " + name + " (" +
        changes_text(p.changes) + ")" + (p.replan ? "; re-planning" : "; tracking again with the same plan"));
    return true;
  }
  rep.stop_reason = rep.not_tried.empty() ? "no lever addresses " + failure.reason : failure.reason + "; no lever left";
  for (const auto& n : rep.not_tried)
    if (n.why.rfind("would take about", 0) == 0) rep.stop_reason = failure.reason + "; the time limit (" + seconds(opt_.time_limit_s) + ") is near";
  return false;
}

bool Search::run(const Stopwatch& t_start) {
  SearchReport& rep = out_.search;
  SearchRound round;
  round.action = "first attempt";
  Stopwatch t_round;
  bool replan = true, done = false;
  for (;;) {
    seen_.insert(search::fingerprint(pb_.agents, extra_));
    Failure f;
    if (replan) f = plan(round, opt_.time_limit_s - t_start.seconds());
    round.horizon = out_.plan.horizon;
    if (f.kind == Failure::None) f = track(round);
    if (f.kind == Failure::None && pb_.guarantee == Guarantee::Continuous) f = certify(round);
    round.outcome = f.kind == Failure::None ? "every agent has a controller" : f.reason;
    round.time_s = t_round.seconds();
    rep.plan_time_s += round.plan_time_s;
    rep.track_time_s += round.track_time_s;
    rep.certify_time_s += round.certify_time_s;
    const std::size_t index = rep.rounds.size() + 1;
    rep.rounds.push_back(round);
    out_.failure = f.kind == Failure::None ? "" : f.reason;
    if (f.kind == Failure::None) {
      rep.stop_reason = pb_.guarantee == Guarantee::Continuous ? "every agent has a controller, certified"
                                                                 : "every agent has a controller";
      done = true;
      break;
    }
    t_round = Stopwatch();  // deciding on the next round is part of it
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

}  // namespace

SolveOutcome solve(const LoadedProblem& loaded, const SolveOptions& opt) {
  const Stopwatch t_start;
  SolveOutcome out;
  out.problem = loaded.problem;
  Problem& pb = out.problem;
  auto log = [&](const std::string& s) {
    if (opt.log) opt.log(s);
  };
  // Each agent's tracker (AgentSpec::tracker, resolved by the loader). An agent without one (a
  // Problem built by hand) gets the top-level tracker, or abcd.
  for (auto& a : pb.agents)
    if (a.tracker.name.empty())
      a.tracker = pb.tracker.name.empty() || pb.tracker.name == kAutoTracker ? PluginChoice{"abcd", {}} : pb.tracker;
  out.trackers = loaded.trackers;
  out.trackers.resize(pb.agents.size());

  Search search(loaded, opt, out);
  const bool controllers = search.run(t_start);
  log("[search] " + out.search.message());

  const bool root = !opt.cluster || opt.cluster->rank() == 0;
  TrackerInstances instances(loaded.registry);
  // The baseline is a figure for the report: rank 0's alone.
  if (root) out.global = attempt_global_abcd(pb, instances, opt, log);
  if (out.global.attempted)
    out.attempts.push_back({"global ABCD", "eta_x, eta_u of the agents, product domain", out.global.status, out.global.time_s, 0});

  if (controllers) {
    std::vector<std::shared_ptr<const Controller>> ctrls;
    for (const auto& a : out.agents) ctrls.push_back(a.track.controller);
    VerificationOptions vo;
    vo.runs = opt.verification_runs;
    vo.threads = opt.threads;
    vo.collective = opt.cluster;
    // A live bar on a terminal (runs, runs/s, time left), else a line every quarter.
    vo.progress = [p = std::make_shared<RunProgress>(opt.log, opt.live)](int done, int total) { (*p)(done, total); };
    out.verification = verify(pb, out.plan.nominal, ctrls, vo);
    out.verification_ran = true;
    out.attempts.push_back({"verify", std::to_string(out.verification.runs) + " runs",
                            std::to_string(out.verification.violations) + " violations", out.verification.time_s,
                            pb.horizon});
    out.verified = out.verification.violations == 0 && out.verification.tube_violations == 0;
    // A closed-loop run cannot certify; it can only refute. "verified" rests on the trackers'
    // guarantee (and, in continuous time, on the certificate above).
    out.failure = out.verified ? "" : "verification found violations (a soundness bug): " + out.verification.worst;
  }
  out.total_time_s = t_start.seconds();
  return out;
}

}  // namespace marsyn
