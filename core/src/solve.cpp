#include "marsyn/core/solve.hpp"

#include <cmath>
#include <map>
#include <sstream>

#include "marsyn/core/problem/agent_checks.hpp"
#include "marsyn/core/tracking/mpi_plan_broadcast.hpp"
#include "marsyn/core/tracking/global_abcd.hpp"
#include "marsyn/core/tracking/track_agents.hpp"
#include "marsyn/core/stopwatch.hpp"

namespace marsyn {
namespace {


std::string vec(const Eigen::VectorXd& v) {
  std::ostringstream s;
  s << "(";
  for (Eigen::Index i = 0; i < v.size(); ++i) s << (i ? "," : "") << v[i];
  return s.str() + ")";
}

// An attempt's parameters for one agent: its tracker, eps, and the grids when it has them.
std::string agent_parameters(const AgentSpec& a) {
  std::string p = "tracker=" + a.tracker.name + " eps=" + vec(a.tube.eps);
  if (a.tube.eta_x.size()) p += " eta_x=" + vec(a.tube.eta_x);
  if (a.tube.eta_u.size()) p += " eta_u=" + vec(a.tube.eta_u);
  return p;
}

}  // namespace

SolveOutcome solve(const LoadedProblem& loaded, const SolveOptions& opt) {
  const Stopwatch t_start;
  const PluginRegistry& reg = *loaded.registry;
  SolveOutcome out;
  out.problem = loaded.problem;
  Problem& pb = out.problem;
  auto log = [&](const std::string& s) {
    if (opt.log) opt.log(s);
  };
  const auto planner = reg.create<Planner>(pb.planner.name, pb.planner.params);
  const auto warm_planner = pb.warm_start_planner.name.empty()
                                ? nullptr
                                : reg.create<Planner>(pb.warm_start_planner.name, pb.warm_start_planner.params);
  // Each agent's tracker (AgentSpec::tracker, resolved by the loader), one object per distinct
  // choice. An agent without one (a Problem built by hand) gets the top-level tracker, or abcd.
  TrackerInstances instances(loaded.registry);
  for (auto& a : pb.agents)
    if (a.tracker.name.empty())
      a.tracker = pb.tracker.name.empty() || pb.tracker.name == kAutoTracker ? PluginChoice{"abcd", {}} : pb.tracker;
  out.trackers = loaded.trackers;
  out.trackers.resize(pb.agents.size());
  auto tracker_of = [&](const AgentSpec& a) { return instances.get(a.tracker); };
  // The checks a proposed eps or tracker setting must pass: core's (bounds, goal) and the tracker's.
  auto acceptable = [&](const AgentSpec& a) {
    return agent_consistent(a) && assess_tracker(instances, a.tracker, a, {pb.horizon, pb.tau, loaded.memory_budget}).ok;
  };

  bool all_tracked = false;
  bool certified = false;
  bool replan = true;  // false when only grids changed: the plan stays valid
  std::map<std::string, double> plan_extra;  // per constraint: grows where certification fell short
  // Over MPI every rank runs this loop in lock step; rank 0's clock decides when time is up.
  const bool root = !opt.cluster || opt.cluster->rank() == 0;
  auto rank0_says = [&](bool mine) {
    if (!opt.cluster || opt.cluster->size() <= 1) return mine;
    std::vector<std::uint8_t> b{static_cast<std::uint8_t>(mine ? 1 : 0)};
    opt.cluster->broadcast(b, 0);
    return b.at(0) != 0;
  };
  for (int iter = 0; iter < opt.max_outer_iterations && rank0_says(t_start.seconds() < opt.time_limit_s); ++iter) {
    if (replan) {
    // 1. Plan (the planning stage lengthens the horizon itself when T fails).
    planning::PlanSearchOptions po;
    po.time_limit_s = std::max(1.0, opt.time_limit_s - t_start.seconds());
    po.log = [&](const std::string& s) { log("[plan] " + s); };
    po.warm_start_planner = warm_planner.get();
    po.assembly.extra = plan_extra;
    std::ostringstream params;
    params << "T=" << pb.horizon;
    if (!plan_extra.empty()) params << " extra clearance for " << plan_extra.size() << " constraint(s)";
    for (const auto& a : pb.agents) params << " eps[" << a.name << "]=" << vec(a.tube.eps);
    log("[plan] " + pb.planner.name + " on the product system (" + std::to_string(pb.product_state_dim()) +
        " states, " + std::to_string(pb.product_input_dim()) + " inputs)");
    if (root) out.plan = planning::plan(pb, *planner, po);
    if (opt.cluster) mpi::broadcast_plan(*opt.cluster, out.plan);  // what the other ranks need of it
    out.attempts.push_back({"plan", params.str(),
                            out.plan.feasible ? "feasible, smallest robust margin " + std::to_string(out.plan.check.min_margin)
                                              : "no feasible plan: " + out.plan.check.message,
                            out.plan.total_time_s});
    if (!out.plan.feasible) {
      // Remark 2: a smaller eps makes the robust specification easier to plan for.
      bool changed = false;
      for (auto& a : pb.agents) {
        AgentSpec b = a;
        b.tube.eps *= 0.8;
        if (b.tube.eta_x.size() == b.tube.eps.size()) b.tube.eta_x = b.tube.eta_x.cwiseMin(b.tube.eps);  // a grid no coarser than the tube
        if (acceptable(b)) {
          a = b;
          changed = true;
        }
      }
      out.failure = "planning failed: " + out.plan.check.message;
      if (!changed) break;
      log("[search] planning failed; shrinking eps by 0.8 and re-planning");
      continue;
    }
    if (!out.plan.nominal.empty()) pb.horizon = out.plan.horizon;
    plan_extra = out.plan.extra;  // a later re-plan keeps the clearance this one needed

    }
    // 2-3. Project and track every agent.
    const Stopwatch t_track;
    out.agents = track_agents(pb, out.plan.nominal, instances.for_agents(pb), opt, loaded.memory_budget);
    all_tracked = true;
    std::vector<int> failed;
    for (std::size_t i = 0; i < out.agents.size(); ++i) {
      const auto& r = out.agents[i].track;
      out.attempts.push_back({"track " + out.agents[i].name, agent_parameters(pb.agents[i]),
                              std::string(to_string(r.status)) + (r.message.empty() ? "" : ": " + r.message),
                              r.stats.abstraction_time_s + r.stats.synthesis_time_s});
      if (r.status != TrackerStatus::ControllerFound) {
        all_tracked = false;
        failed.push_back(static_cast<int>(i));
      }
    }
    log("[track] all agents in " + std::to_string(t_track.seconds()) + " s");
    if (all_tracked) {
      if (pb.guarantee == Guarantee::Sampled) break;
      // 4. Certify the spec on the period enclosures (continuous time).
      std::vector<std::shared_ptr<const Controller>> ctrls;
      for (const auto& a : out.agents) ctrls.push_back(a.track.controller);
      out.certification = certify(pb, ctrls);
      out.certification_ran = true;
      log("[certify] " + out.certification.message);
      out.attempts.push_back({"certify", std::to_string(out.certification.enclosures) + " period enclosures",
                              out.certification.message, out.certification.time_s});
      certified = out.certification.certified;
      if (certified) break;
      out.failure = "certification failed: " + out.certification.message;
      const double shortfall = -out.certification.min_margin;
      if (!std::isfinite(shortfall) || !(shortfall > 0)) break;
      // Remark 2 between the samples: more room in the robust plan exactly where the tubes'
      // period enclosures came too close (1.5 times the shortfall), then track again.
      for (const auto& [name, m] : out.certification.shortfalls) plan_extra[name] += 1.5 * -m;
      replan = true;
      all_tracked = false;
      std::string who;
      for (int i : out.certification.failing_agents) who += " " + pb.agents[i].name;
      log("[search] period enclosures short by " + std::to_string(shortfall) + " (agents" + who + "; " +
          std::to_string(out.certification.shortfalls.size()) +
          " requirement(s)); re-planning with more clearance for them");
      continue;
    }
    // Only "no controller" is a reason to change parameters; bad input or an exhausted budget
    // would fail the same way again.
    bool searchable = true;
    for (int i : failed)
      if (out.agents[i].track.status != TrackerStatus::NoController) {
        searchable = false;
        out.failure = "tracking " + pb.agents[i].name + ": " + to_string(out.agents[i].track.status) +
                      (out.agents[i].track.message.empty() ? "" : ": " + out.agents[i].track.message);
      }
    if (!searchable) break;
    out.failure = "no controller for";
    for (int i : failed) out.failure += " " + pb.agents[i].name;
    // tracker: auto: a failed agent first moves to the next tracker that accepted it (same eps,
    // so the plan stays valid). Remark 2 for the others: a wider tube (first) or the tracker's own
    // refinement (then; abcd: finer grids), and the team is re-planned with the new eps.
    bool changed = false, eps_changed = false;
    std::string fell_back, searched;
    for (int i : failed) {
      AgentSpec& a = pb.agents[i];
      AgentTrackers& choice = out.trackers[i];
      bool switched = false;
      while (choice.automatic && !choice.fallbacks.empty() && !switched) {
        AgentSpec b = a;
        b.tracker = choice.fallbacks.front();
        choice.fallbacks.erase(choice.fallbacks.begin());
        const TrackerAssessment as = assess_tracker(instances, b.tracker, b, {pb.horizon, pb.tau, loaded.memory_budget});
        if (!as.ok) continue;
        fell_back += (fell_back.empty() ? "" : ", ") + a.name + ": " + a.tracker.name + " -> " + b.tracker.name;
        choice.assessment = as;
        a = b;
        switched = true;
      }
      if (switched) {
        changed = true;
        continue;
      }
      AgentSpec b = a;
      bool proposed = true;
      if (iter % 2 == 0) b.tube.eps *= 1.25;
      else proposed = tracker_of(b)->refine(b);
      if (proposed && acceptable(b)) {
        a = b;
        changed = true;
        eps_changed = eps_changed || iter % 2 == 0;
        searched += " " + a.name + (iter % 2 == 0 ? "" : " (" + a.tracker.name + ")");
      }
    }
    replan = eps_changed;  // eps changes the robust spec; another tracker or its own knobs do not
    if (!changed) break;
    if (!fell_back.empty())
      log("[search] " + out.failure + "; tracker: auto falls back (" + fell_back + ") with the same eps");
    if (!searched.empty())
      log("[search] " + out.failure + "; " + (iter % 2 == 0 ? "enlarging the eps of" : "refining the trackers of") +
          searched + (replan ? " and re-planning" : " and tracking again"));
  }

  // The baseline is a figure for the report: rank 0's alone.
  if (root) out.global = attempt_global_abcd(pb, instances, opt, log);
  if (out.global.attempted)
    out.attempts.push_back({"global ABCD", "eta_x, eta_u of the agents, product domain", out.global.status, out.global.time_s});

  if (out.plan.feasible && all_tracked && (certified || pb.guarantee == Guarantee::Sampled)) {
    std::vector<std::shared_ptr<const Controller>> ctrls;
    for (const auto& a : out.agents) ctrls.push_back(a.track.controller);
    VerificationOptions vo;
    vo.runs = opt.verification_runs;
    vo.threads = opt.threads;
    vo.collective = opt.cluster;
    int last_pct = -1;
    vo.progress = [&](int done, int total) {
      const int pct = 100 * done / total;
      if (pct / 25 != last_pct / 25) {
        last_pct = pct;
        log("[verify] " + std::to_string(done) + "/" + std::to_string(total) + " closed-loop runs");
      }
    };
    out.verification = verify(pb, out.plan.nominal, ctrls, vo);
    out.verification_ran = true;
    out.attempts.push_back({"verify", std::to_string(out.verification.runs) + " runs",
                            std::to_string(out.verification.violations) + " violations",
                            out.verification.time_s});
    out.verified = out.verification.violations == 0 && out.verification.tube_violations == 0;
    // A closed-loop run cannot certify; it can only refute. "verified" rests on the trackers'
    // guarantee (and, in continuous time, on the certificate above).
    out.failure = out.verified ? "" : "verification found violations (a soundness bug): " + out.verification.worst;
  }
  out.total_time_s = t_start.seconds();
  return out;
}

}  // namespace marsyn
