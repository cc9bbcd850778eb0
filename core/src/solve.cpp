#include "marsyn/core/solve.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "marsyn/core/problem/agent_checks.hpp"
#include "marsyn/core/tracking/global_abcd.hpp"
#include "marsyn/core/report/output_folder.hpp"
#include "marsyn/core/report/report_html.hpp"

namespace fs = std::filesystem;

namespace marsyn {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string vec(const Eigen::VectorXd& v) {
  std::ostringstream s;
  s << "(";
  for (Eigen::Index i = 0; i < v.size(); ++i) s << (i ? "," : "") << v[i];
  return s.str() + ")";
}

// An attempt's parameters for one agent: its tracker, eps, and the grids when it has them.
std::string agent_parameters(const AgentSpec& a) {
  std::string p = "tracker=" + a.tracker.name + " eps=" + vec(a.eps);
  if (a.eta_x.size()) p += " eta_x=" + vec(a.eta_x);
  if (a.eta_u.size()) p += " eta_u=" + vec(a.eta_u);
  return p;
}

}  // namespace

TrackingProblem tracking_problem(const Problem& pb, int index, const NominalTrajectory& nominal) {
  const AgentSpec& a = pb.agents[index];
  TrackingProblem tp;
  tp.agent = a.name;
  tp.dynamics = a.dynamics;
  tp.nominal = nominal;
  tp.eps = a.eps;
  tp.eta_x = a.eta_x;
  tp.eta_u = a.eta_u;
  tp.w = a.w;
  tp.input_bounds = a.input_bounds;
  tp.state_bounds = a.state_bounds;
  tp.tau = pb.tau;
  tp.workspace = a.workspace;
  return tp;
}

std::vector<AgentOutcome> track_agents(const Problem& pb, const std::vector<NominalTrajectory>& nominal,
                                       const std::vector<std::shared_ptr<const Tracker>>& trackers,
                                       const SolveOptions& opt) {
  const int N = static_cast<int>(pb.agents.size());
  std::vector<AgentOutcome> out(N);
  // Agents in parallel, one tracker thread each, when the work is spread over them; when one
  // agent dominates (the crane beside a vehicle: 4 vs 2 dimensions), agents run one after the
  // other with all threads each. Work estimate: each agent's tracker's own (assess().work_s).
  std::vector<double> work_estimate(N, 0.0);
  double total_work = 0, max_work = 0;
  for (int i = 0; i < N; ++i) {
    const double w =
        std::max(0.0, assess_tracker(*trackers[i], pb.agents[i], static_cast<int>(nominal[i].x.size()) - 1, pb.tau).work_s);
    work_estimate[i] = w;
    total_work += w;
    max_work = std::max(max_work, w);
  }
  const bool dominated = N < opt.threads || max_work > 0.5 * total_work;
  const int workers = dominated ? 1 : std::max(1, std::min(opt.threads, N));
  TrackOptions topt;
  topt.threads = dominated ? opt.threads : 1;
  std::atomic<int> next{0}, done{0};
  std::mutex log_mutex;
  std::vector<char> running(N, 0);
  auto work = [&] {
    for (int i = next++; i < N; i = next++) {
      {
        std::lock_guard<std::mutex> lock(log_mutex);
        running[i] = 1;
      }
      const AgentSpec& a = pb.agents[i];
      const TrackingProblem tp = tracking_problem(pb, i, nominal[i]);
      const auto t0 = Clock::now();
      out[i].name = a.name;
      out[i].tracker = a.tracker.name;
      try {
        out[i].track = trackers[i]->track(tp, topt);
      } catch (const std::exception& e) {
        out[i].track.status = TrackerStatus::InvalidInput;
        out[i].track.message = e.what();
      }
      const int d = ++done;
      if (opt.log) {
        std::lock_guard<std::mutex> lock(log_mutex);
        running[i] = 0;
        std::ostringstream s;
        s << "[track " << d << "/" << N << "] " << a.name << " (" << a.tracker.name
          << "): " << to_string(out[i].track.status) << ", ";
        // Grid figures only from a tracker that has a grid.
        if (out[i].track.stats.tube_cells > 0)
          s << out[i].track.stats.tube_cells << " tube cells, N_l " << out[i].track.stats.state_input_pairs << ", ";
        s << out[i].track.stats.boxes_computed << " boxes, " << since(t0) << " s";
        if (!out[i].track.message.empty()) s << " (" << out[i].track.message << ")";
        opt.log(s.str());
      }
    }
  };
  // A heartbeat, so that a long abstraction (minutes for a 4-dimensional agent) is visibly alive.
  std::mutex beat_mutex;
  std::condition_variable beat_cv;
  bool finished = false;
  std::thread heartbeat([&] {
    const auto t0 = Clock::now();
    std::unique_lock<std::mutex> lock(beat_mutex);
    while (!beat_cv.wait_for(lock, std::chrono::seconds(15), [&] { return finished; })) {
      if (!opt.log) continue;
      std::lock_guard<std::mutex> log_lock(log_mutex);
      std::string names;
      for (int i = 0; i < N; ++i)
        if (running[i]) names += (names.empty() ? "" : ", ") + pb.agents[i].name;
      std::ostringstream s;
      s << "[track] " << done.load() << "/" << N << " agents done after " << static_cast<int>(since(t0))
        << " s; still working on " << (names.empty() ? "-" : names);
      opt.log(s.str());
    }
  });
  std::vector<std::thread> pool;
  for (int t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  {
    std::lock_guard<std::mutex> lock(beat_mutex);
    finished = true;
  }
  beat_cv.notify_all();
  heartbeat.join();
  return out;
}

GlobalAbcdEstimate estimate_global_abcd(const Problem& pb) {
  GlobalAbcdEstimate g;
  for (const auto& a : pb.agents)
    if (a.eta_x.size() != a.n() || a.eta_u.size() != a.m()) {
      g.status = "skipped: " + a.name + " has no eta_x and eta_u (the baseline abstracts the product on the agents' grids)";
      return g;
    }
  double pairs = 1;
  for (const auto& a : pb.agents) {
    for (int i = 0; i < a.n(); ++i) pairs *= std::ceil((a.state_bounds.hi[i] - a.state_bounds.lo[i]) / a.eta_x[i]);
    for (int j = 0; j < a.m(); ++j)
      pairs *= std::floor((a.input_bounds.hi[j] - a.input_bounds.lo[j]) / a.eta_u[j] + 1e-9) + 1;
  }
  g.state_input_pairs = pairs;
  // A SCOTS-style transition table stores at least one 64-bit successor range per pair.
  g.memory_bytes_estimate = pairs * 8.0;
  return g;
}

SolveOutcome solve(const LoadedProblem& loaded, const SolveOptions& opt) {
  const auto t_start = Clock::now();
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
    return agent_consistent(a) && assess_tracker(instances, a.tracker, a, pb.horizon, pb.tau).ok;
  };

  bool all_tracked = false;
  bool certified = false;
  bool replan = true;  // false when only grids changed: the plan stays valid
  std::map<std::string, double> plan_extra;  // per constraint: grows where certification fell short
  for (int iter = 0; iter < opt.max_outer_iterations && since(t_start) < opt.time_limit_s; ++iter) {
    if (replan) {
    // 1. Plan (the planning stage lengthens the horizon itself when T fails).
    planning::PlanSearchOptions po;
    po.time_limit_s = std::max(1.0, opt.time_limit_s - since(t_start));
    po.log = [&](const std::string& s) { log("[plan] " + s); };
    po.warm_start_planner = warm_planner.get();
    po.assembly.extra = plan_extra;
    std::ostringstream params;
    params << "T=" << pb.horizon;
    if (!plan_extra.empty()) params << " extra clearance for " << plan_extra.size() << " constraint(s)";
    for (const auto& a : pb.agents) params << " eps[" << a.name << "]=" << vec(a.eps);
    log("[plan] " + pb.planner.name + " on the product system (" + std::to_string(pb.product_state_dim()) +
        " states, " + std::to_string(pb.product_input_dim()) + " inputs)");
    out.plan = planning::plan(pb, *planner, po);
    out.attempts.push_back({"plan", params.str(),
                            out.plan.feasible ? "feasible, smallest robust margin " + std::to_string(out.plan.check.min_margin)
                                              : "no feasible plan: " + out.plan.check.message,
                            out.plan.total_time_s});
    if (!out.plan.feasible) {
      // Remark 2: a smaller eps makes the robust specification easier to plan for.
      bool changed = false;
      for (auto& a : pb.agents) {
        AgentSpec b = a;
        b.eps *= 0.8;
        if (b.eta_x.size() == b.eps.size()) b.eta_x = b.eta_x.cwiseMin(b.eps);  // a grid no coarser than the tube
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
    if (!out.plan.agents.empty()) pb.horizon = out.plan.horizon;
    plan_extra = out.plan.extra;  // a later re-plan keeps the clearance this one needed

    }
    // 2-3. Project and track every agent.
    const auto t_track = Clock::now();
    out.agents = track_agents(pb, out.plan.agents, instances.for_agents(pb), opt);
    all_tracked = true;
    std::vector<int> failed;
    for (std::size_t i = 0; i < out.agents.size(); ++i) {
      const auto& r = out.agents[i].track;
      out.attempts.push_back({"track " + out.agents[i].name, agent_parameters(pb.agents[i]),
                              std::string(to_string(r.status)) + (r.message.empty() ? "" : ": " + r.message),
                              r.stats.abstraction_time_s + r.stats.synthesis_time_s});
      if (r.status != TrackerStatus::Controller) {
        all_tracked = false;
        failed.push_back(static_cast<int>(i));
      }
    }
    log("[track] all agents in " + std::to_string(since(t_track)) + " s");
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
        const TrackerAssessment as = assess_tracker(instances, b.tracker, b, pb.horizon, pb.tau);
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
      if (iter % 2 == 0) b.eps *= 1.25;
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

  out.global = estimate_global_abcd(pb);
  if (!out.global.status.empty()) {
    // estimate_global_abcd said why not
  } else if (!reg.find(PluginKind<Tracker>::name, "abcd")) {
    out.global.status = "skipped: the abcd tracker is not installed";
  } else if (out.global.memory_bytes_estimate > opt.global_memory_budget_bytes) {
    out.global.status = opt.global_memory_budget_bytes <= 0 ? "skipped: disabled (--global-budget 0)"
                                                             : "skipped: the estimate exceeds the memory budget";
  } else if (pb.agents.size() < 2) {
    out.global.status = "skipped: a single agent has no product to abstract";
  } else if (!pb.formation.empty()) {
    out.global.status = "skipped: formation constraints are not supported by the global baseline";
  } else {
    log("[global] abstraction of the product system over its whole domain (" +
        std::to_string(out.global.state_input_pairs) + " state-input pairs)");
    // The baseline is abcd's whole-domain mode, whatever tracks the agents: with the parameters
    // the problem gives abcd (the first agent's that uses it), else its defaults.
    PluginChoice abcd{"abcd", {}};
    for (const auto& a : pb.agents)
      if (a.tracker.name == "abcd") {
        abcd = a.tracker;
        break;
      }
    const GlobalAbcdRun g = run_global_abcd(pb, *instances.get(abcd), opt.threads, opt.global_memory_budget_bytes);
    out.global.status = g.status;
    out.global.time_s = g.time_s;
    out.global.boxes_computed = g.boxes_computed;
    out.attempts.push_back({"global ABCD", "eta_x, eta_u of the agents, product domain", g.status, g.time_s});
    log("[global] " + g.status + " in " + std::to_string(g.time_s) + " s");
  }

  if (out.plan.feasible && all_tracked && (certified || pb.guarantee == Guarantee::Sampled)) {
    std::vector<std::shared_ptr<const Controller>> ctrls;
    for (const auto& a : out.agents) ctrls.push_back(a.track.controller);
    VerificationOptions vo;
    vo.runs = opt.verification_runs;
    vo.threads = opt.threads;
    int last_pct = -1;
    vo.progress = [&](int done, int total) {
      const int pct = 100 * done / total;
      if (pct / 25 != last_pct / 25) {
        last_pct = pct;
        log("[verify] " + std::to_string(done) + "/" + std::to_string(total) + " closed-loop runs");
      }
    };
    out.verification = verify(pb, out.plan.agents, ctrls, vo);
    out.verification_ran = true;
    out.attempts.push_back({"verify", std::to_string(out.verification.runs) + " runs",
                            std::to_string(out.verification.violations) + " violations",
                            out.verification.time_s});
    out.verified = out.verification.violations == 0 && out.verification.tube_violations == 0;
    // A closed-loop run cannot certify; it can only refute. "verified" rests on the trackers'
    // guarantee (and, in continuous time, on the certificate above).
    out.failure = out.verified ? "" : "verification found violations (a soundness bug): " + out.verification.worst;
  }
  out.total_time_s = since(t_start);
  return out;
}

namespace {

// Per open-loop run, each part of the specification with its smallest margin and step (null
// when the problem has no such part).
nlohmann::json open_loop_runs_json(const std::vector<OpenLoopRun>& runs) {
  using nlohmann::json;
  auto part = [](const OpenLoopRun::Part& p) {
    return p.step < 0 ? json(nullptr) : json{{"margin", p.margin}, {"step", p.step}};
  };
  json out = json::array();
  for (const auto& r : runs)
    out.push_back({{"disturbance", r.label},
                   {"satisfied", r.satisfied},
                   {"obstacle", part(r.obstacle)},
                   {"collision", part(r.collision)},
                   {"formation", part(r.formation)},
                   {"goal_margin", r.goal < 1e299 ? json(r.goal) : json(nullptr)}});
  return out;
}

}  // namespace

nlohmann::json result_json(const SolveOutcome& o) {
  using nlohmann::json;
  json j;
  j["status"] = o.verified ? "verified" : "failed";
  if (!o.failure.empty()) j["failure"] = o.failure;
  j["problem"] = o.problem.name;
  // Which times the result holds for: every t in [0, T tau], or only t = k tau.
  j["guarantee"] = to_string(o.problem.guarantee);
  j["tracker"] = o.problem.tracker.name;  // the request: a tracker or "auto"; each agent's is agents[i].tracker.name
  j["plan"] = {{"planner", o.problem.planner.name},
               {"status", o.plan.feasible ? "feasible" : to_string(o.plan.result.status)},
               {"time_s", o.plan.total_time_s},
               {"horizon", o.plan.horizon},
               {"iterations", o.plan.result.iterations},
               {"min_robust_margin", o.plan.check.min_margin},
               {"worst_constraint", o.plan.check.worst},
               {"sampled_robust_margin", o.plan.check.sampled_margin},
               {"between_samples_robust_margin",
                o.plan.check.continuous ? json(o.plan.check.between_margin) : json(nullptr)}};
  json agents = json::array();
  for (std::size_t i = 0; i < o.agents.size(); ++i) {
    const auto& a = o.agents[i];
    const auto& s = a.track.stats;
    const AgentTrackers* choice = i < o.trackers.size() ? &o.trackers[i] : nullptr;
    json t = {{"name", a.tracker.empty() ? o.problem.agents[i].tracker.name : a.tracker},
              {"chosen", choice && choice->automatic ? "auto" : "given"},
              {"assessment", choice ? json(choice->assessment.summary) : json(nullptr)},
              {"status", to_string(a.track.status)},
              {"state_input_pairs", s.state_input_pairs},
              {"tube_cells", s.tube_cells},
              {"boxes_computed", s.boxes_computed},
              {"abstraction_time_s", s.abstraction_time_s},
              {"synthesis_time_s", s.synthesis_time_s},
              {"peak_memory_bytes", s.peak_memory_bytes},
              {"initial_state_winning", s.initial_state_winning},
              {"enclosure_substeps", s.enclosure_substeps},
              {"enclosure_time_s", s.enclosure_time_s},
              {"period_enclosures", a.track.controller ? json(a.track.controller->period_enclosures().size()) : json(0)}};
    if (!a.track.message.empty()) t["message"] = a.track.message;
    const AgentSpec& spec = o.problem.agents[i];
    agents.push_back({{"name", a.name},
                      {"dynamics", spec.dynamics_type},
                      {"eps", std::vector<double>(spec.eps.data(), spec.eps.data() + spec.eps.size())},
                      {"eta_x", std::vector<double>(spec.eta_x.data(), spec.eta_x.data() + spec.eta_x.size())},
                      {"eta_u", std::vector<double>(spec.eta_u.data(), spec.eta_u.data() + spec.eta_u.size())},
                      {"tracker", t},
                      {"controller", a.controller_file.empty() ? json(nullptr) : json(a.controller_file)}});
  }
  j["agents"] = agents;
  const auto& c = o.certification;
  auto part = [](const CertifiedPart& p) {
    return std::isfinite(p.margin) ? json{{"margin", p.margin}, {"where", p.where}, {"step", p.step}}
                                   : json(nullptr);
  };
  j["certification"] = {{"ran", o.certification_ran},
                        {"certified", c.certified},
                        {"message", c.message},
                        {"period_enclosures", c.enclosures},
                        {"min_margin", o.certification_ran && std::isfinite(c.min_margin) ? json(c.min_margin) : json(nullptr)},
                        {"state_bounds", part(c.state_bounds)},
                        {"obstacle", part(c.obstacle)},
                        {"collision", part(c.collision)},
                        {"formation", part(c.formation)},
                        {"time_s", c.time_s}};
  const auto& v = o.verification;
  auto margin = [](double m) { return m < 1e299 ? json(m) : json(nullptr); };
  j["verification"] = {{"ran", o.verification_ran},
                       {"guarantee", v.continuous ? "continuous" : "sampled"},
                       {"dense_resolution_s", v.dense_resolution_s},
                       {"sampled_min_margin", o.verification_ran ? margin(v.sampled_min_margin) : json(nullptr)},
                       {"between_samples",
                        {{"min_margin", o.verification_ran ? margin(v.between.min()) : json(nullptr)},
                         {"obstacle", margin(v.between.obstacle)},
                         {"collision", margin(v.between.collision)},
                         {"formation", margin(v.between.formation)},
                         {"violating_runs", v.between_violations},
                         {"worst", v.between_worst}}},
                       {"runs", v.runs},
                       {"violations", v.violations},
                       {"tube_violations", v.tube_violations},
                       {"outside_domain", v.outside_domain},
                       {"min_margin", o.verification_ran ? json(v.min_margin) : json(nullptr)},
                       {"worst", v.worst},
                       {"time_s", v.time_s}};
  j["open_loop"] = {{"runs", v.open_loop_runs},
                    {"violations", v.open_loop_violations},
                    {"min_margin", o.verification_ran ? json(v.open_loop_min_margin) : json(nullptr)},
                    {"worst", v.open_loop_worst},
                    {"by_run", open_loop_runs_json(v.open_loop)}};
  j["global_abcd"] = {{"state_input_pairs", o.global.state_input_pairs},
                      {"memory_bytes_estimate", o.global.memory_bytes_estimate},
                      {"status", o.global.status},
                      {"time_s", o.global.time_s},
                      {"boxes_computed", o.global.boxes_computed}};
  json att = json::array();
  for (const auto& a : o.attempts)
    att.push_back({{"stage", a.stage}, {"parameters", a.parameters}, {"outcome", a.outcome}, {"time_s", a.time_s}});
  j["attempts"] = att;
  j["total_time_s"] = o.total_time_s;
  return j;
}

namespace {
std::vector<std::string> write_into(const std::string& dir, SolveOutcome& o);
}

// The output rule (docs/problem-format.md, "Output files"): a verified solve writes result.json,
// report.html, plan.json and one <agent>.ctrl per agent; a failed one writes only result.json
// (status "failed" and the reason) and report.html. Everything goes through OutputFolder (plain
// names, checked after path resolution to lie in `dir`). Files are staged in a hidden folder
// inside `dir` and moved in only when all are written, so a failure part-way never leaves a
// half-written result; marsyn's own earlier files for this problem are replaced, nothing else in
// `dir` is touched.
std::vector<std::string> write_solve_outputs(const std::string& dir, SolveOutcome& o) {
  const OutputFolder folder(dir);
  const fs::path staging = folder.path(".marsyn-partial");
  fs::remove_all(staging);
  fs::create_directory(staging);
  try {
    auto files = write_into(staging.string(), o);
    std::vector<std::string> previous = {"result.json", "report.html", "plan.json"};
    for (const auto& a : o.problem.agents) previous.push_back(a.name + ".ctrl");
    for (const auto& f : previous) fs::remove(folder.path(f));
    for (const auto& f : files) fs::rename(staging / f, folder.path(f));
    fs::remove_all(staging);
    return files;
  } catch (...) {
    std::error_code ec;
    fs::remove_all(staging, ec);
    throw;
  }
}

namespace {
std::vector<std::string> write_into(const std::string& dir, SolveOutcome& o) {
  std::vector<std::string> files;
  const bool failed = !o.verified;  // a failure writes only result.json and report.html
  for (auto& a : o.agents) a.controller_file.clear();
  for (auto& a : o.agents) {
    if (failed || !a.track.controller) continue;
    a.controller_file = a.name + ".ctrl";
    a.track.controller->write((fs::path(dir) / a.controller_file).string());
    files.push_back(a.controller_file);
  }
  if (!failed && !o.plan.plan.u.empty()) {
    planning::write_plan_json((fs::path(dir) / "plan.json").string(), o.problem, o.plan);
    files.push_back("plan.json");
  }
  const nlohmann::json result = result_json(o);
  {
    std::ofstream f(fs::path(dir) / "result.json");
    f << result.dump(2) << "\n";
    if (!f) throw std::runtime_error("cannot write " + (fs::path(dir) / "result.json").string());
  }
  files.push_back("result.json");
  std::vector<const std::vector<PeriodEnclosure>*> enclosures;
  for (const auto& a : o.agents) enclosures.push_back(a.track.controller ? &a.track.controller->period_enclosures() : nullptr);
  const nlohmann::json scene =
      report_scene(o.problem, o.plan.agents, o.verification_ran ? &o.verification : nullptr, enclosures);
  write_report_html((fs::path(dir) / "report.html").string(), result, scene);
  files.push_back("report.html");
  return files;
}
}  // namespace

}  // namespace marsyn
