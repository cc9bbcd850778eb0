#include "marsyn/core/report/result_json.hpp"

#include <algorithm>
#include <cmath>

#include "marsyn/core/planning/mission.hpp"

namespace marsyn {

nlohmann::json figure_json(const TrackerFigure::Value& value) {
  return std::visit([](const auto& v) { return nlohmann::json(v); }, value);
}

void add_figures(nlohmann::json& into, const TrackerStats& stats) {
  for (const auto& f : stats.figures) into[f.name] = figure_json(f.value);
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

// What the file left to marsyn for agent i (docs/parameters.md): the fields, the rules that gave
// their first values, and how the search narrowed an auto eps.
nlohmann::json auto_json(const SolveOutcome& o, std::size_t i) {
  const AutoTube& at = o.auto_tube[i];
  nlohmann::json fields = nlohmann::json::array();
  if (at.eps) fields.push_back("eps");
  for (const auto& f : at.fields) fields.push_back(f);
  AgentSpec first = o.problem.agents[i];
  std::string eps_rule;
  first.tube.eps = first_auto_eps(first, o.problem.tau, &eps_rule);
  if (std::string cap; cap_auto_eps_for_formation(first, formation_tolerance(o.problem, static_cast<int>(i)), &cap))
    eps_rule += "; " + cap;
  nlohmann::json j{{"fields", fields}};
  if (at.eps) j["eps_rule"] = eps_rule + "; then the tube the controller kept at the samples + " +
                              std::to_string(static_cast<int>(100 * kAutoEpsMargin)) + " %, never below " +
                              std::to_string(static_cast<int>(100 * kAutoEpsFloor)) + " % of the first value, at most " +
                              std::to_string(kAutoEpsIterations) + " times";
  // The owners' rule for their automatic fields (abcd: its grid), under the key it always had.
  if (!at.fields.empty()) j["grid_rule"] = at.field_rule;
  j["search"] = auto_search_note(o, i);
  return j;
}

// The search (docs/search.md): why it stopped, and per round the action, its reason, what it
// changed and where the round's time went. Times are totals; the rounds give the split.
nlohmann::json search_json(const SearchReport& s) {
  using nlohmann::json;
  json rounds = json::array();
  for (const auto& r : s.rounds) {
    json changes = json::array();
    for (const auto& c : r.changes)
      changes.push_back({{"agent", c.agent.empty() ? json(nullptr) : json(c.agent)}, {"what", c.what}, {"from", c.from}, {"to", c.to}});
    rounds.push_back({{"round", r.index},
                      {"action", r.action},
                      {"reason", r.reason.empty() ? json(nullptr) : json(r.reason)},
                      {"changes", changes},
                      {"planned", r.planned},
                      {"horizon", r.horizon},
                      {"outcome", r.outcome},
                      {"plan_time_s", r.plan_time_s},
                      {"track_time_s", r.track_time_s},
                      {"certify_time_s", r.certify_time_s},
                      {"time_s", r.time_s},
                      {"undone", r.undone}});
  }
  json not_tried = json::array();
  for (const auto& n : s.not_tried) not_tried.push_back({{"lever", n.lever}, {"why", n.why}});
  return {{"stop_message", s.message()},      {"stopped", s.stop_reason},     {"tried", s.tried()},
          {"not_tried", not_tried},      {"time_limit_s", s.time_limit_s}, {"time_s", s.time_s},
          {"plan_time_s", s.plan_time_s}, {"track_time_s", s.track_time_s}, {"certify_time_s", s.certify_time_s},
          {"rounds", rounds}};
}

// An agent's tracking time summed over every round that tracked it.
double tracking_time_all_rounds(const SolveOutcome& o, const std::string& agent) {
  double t = 0;
  for (const auto& a : o.attempts)
    if (a.stage == "track " + agent) t += a.time_s;
  return t;
}

// A margin, or null where none was measured (the reports' 1e300).
nlohmann::json margin_json(double m) { return m < 1e299 ? nlohmann::json(m) : nlohmann::json(nullptr); }

// A certified part's smallest margin with where and when, or null where the part is absent.
nlohmann::json certified_part_json(const CertifiedPart& p) {
  return std::isfinite(p.margin) ? nlohmann::json{{"margin", p.margin}, {"where", p.where}, {"step", p.step}}
                                 : nlohmann::json(nullptr);
}

nlohmann::json plan_json(const SolveOutcome& o) {
  using nlohmann::json;
  return {{"planner", o.problem.planner.name},
          {"status", o.plan.feasible ? "feasible" : to_string(o.plan.result.status)},
          {"time_s", o.search.plan_time_s},  // every round's planning; search.rounds has the split
          {"last_round_time_s", o.plan.total_time_s},
          {"horizon", o.plan.horizon},
          {"iterations", o.plan.result.iterations},
          {"min_robust_margin", o.plan.check.min_margin},
          {"worst_constraint", o.plan.check.worst},
          {"sampled_robust_margin", o.plan.check.sampled_margin},
          {"between_samples_robust_margin", o.plan.check.continuous ? json(o.plan.check.between_margin) : json(nullptr)}};
}

// Agent i of the problem, tracked or not (a failed plan tracks none).
nlohmann::json agent_json(const SolveOutcome& o, std::size_t i) {
  using nlohmann::json;
  const bool tracked = i < o.agents.size();
  const AgentOutcome a = tracked ? o.agents[i] : AgentOutcome{o.problem.agents[i].name, "", {}, ""};
  const auto& s = a.track.stats;
  const AgentTrackers* choice = i < o.trackers.size() ? &o.trackers[i] : nullptr;
  json t = {{"name", a.tracker.empty() ? o.problem.agents[i].tracker.name : a.tracker},
            {"chosen", choice && choice->automatic ? "auto" : "given"},
            {"assessment", choice ? json(choice->assessment.summary) : json(nullptr)},
            {"status", tracked ? to_string(a.track.status) : "not tracked"},
            {"all_rounds_time_s", tracking_time_all_rounds(o, a.name)},
            {"state_input_pairs", s.state_input_pairs},
            {"boxes_computed", s.boxes_computed},
            {"abstraction_time_s", s.abstraction_time_s},
            {"synthesis_time_s", s.synthesis_time_s},
            {"peak_memory_bytes", s.peak_memory_bytes},
            {"enclosure_substeps", s.enclosure_substeps},
            {"enclosure_time_s", s.enclosure_time_s},
            {"period_enclosures", a.track.controller ? json(a.track.controller->period_enclosures().size()) : json(0)}};
  // What this tracker alone measures (abcd: tube_cells, initial_state_winning, the winning
  // cells per step), as it declares it.
  add_figures(t, s);
  if (!a.track.message.empty()) t["message"] = a.track.message;
  const AgentSpec& spec = o.problem.agents[i];
  json j = {{"name", a.name},
            {"dynamics", spec.dynamics_type},
            {"eps", std::vector<double>(spec.tube.eps.data(), spec.tube.eps.data() + spec.tube.eps.size())},
            {"tracker", t},
            {"controller", a.controller_file.empty() ? json(nullptr) : json(a.controller_file)}};
  // The trackers' own fields (abcd: eta_x, eta_u), by name.
  for (const auto& f : spec.fields.items) j[f.name] = std::vector<double>(f.value.data(), f.value.data() + f.value.size());
  // The stated initial set the controller was made to accept (--resume keeps it only for the same).
  if (spec.radius > 0) j["radius"] = spec.radius;
  json more = json::array();  // every body when the agent lists them: its own point first
  if (!spec.body.empty()) more.push_back({{"name", spec.body}, {"radius", spec.radius}});
  for (const auto& e : o.problem.extra_bodies)
    if (e.agent == static_cast<int>(i)) more.push_back({{"name", e.body}, {"radius", e.spec.radius}});
  if (!more.empty()) j["bodies"] = more;
  if (spec.x0_radius.size()) j["x0_radius"] = std::vector<double>(spec.x0_radius.data(), spec.x0_radius.data() + spec.x0_radius.size());
  // W (its largest value over X and U), and where it grows with the state or input its formula.
  j["w"] = std::vector<double>(spec.tube.w.data(), spec.tube.w.data() + spec.tube.w.size());
  if (spec.tube.state_dependent()) {
    json per = json::object();
    for (const auto& g : spec.tube.w_growth) per[g.name] = std::vector<double>(g.gain.data(), g.gain.data() + g.gain.size());
    j["w_base"] = std::vector<double>(spec.tube.w_base.data(), spec.tube.w_base.data() + spec.tube.w_base.size());
    j["w_per"] = per;
  }
  if (i < o.auto_tube.size() && o.auto_tube[i].any()) j["auto"] = auto_json(o, i);
  return j;
}

nlohmann::json certification_json(const SolveOutcome& o) {
  using nlohmann::json;
  const auto& c = o.certification;
  return {{"ran", o.certification_ran},
          {"certified", c.certified},
          {"message", c.message},
          {"period_enclosures", c.enclosures},
          {"min_margin", o.certification_ran && std::isfinite(c.min_margin) ? json(c.min_margin) : json(nullptr)},
          {"state_bounds", certified_part_json(c.state_bounds)},
          {"obstacle", certified_part_json(c.obstacle)},
          {"collision", certified_part_json(c.collision)},
          {"formation", certified_part_json(c.formation)},
          {"time_s", c.time_s}};
}

nlohmann::json verification_json(const SolveOutcome& o) {
  using nlohmann::json;
  const auto& v = o.verification;
  return {{"ran", o.verification_ran},
          {"guarantee", v.continuous ? "continuous" : "sampled"},
          {"dense_resolution_s", v.dense_resolution_s},
          {"sampled_min_margin", o.verification_ran ? margin_json(v.sampled_min_margin) : json(nullptr)},
          {"between_samples",
           {{"min_margin", o.verification_ran ? margin_json(v.between.min()) : json(nullptr)},
            {"obstacle", margin_json(v.between.obstacle)},
            {"collision", margin_json(v.between.collision)},
            {"formation", margin_json(v.between.formation)},
            {"violating_runs", v.between_violations},
            {"worst", v.between_worst}}},
          {"runs", v.runs},
          {"violations", v.violations},
          {"tube_violations", v.tube_violations},
          {"outside_domain", v.outside_domain},
          {"min_margin", o.verification_ran ? json(v.min_margin) : json(nullptr)},
          {"worst", v.worst},
          {"time_s", v.time_s},
          {"runs_time_s", v.runs_time_s}};  // runs / runs_time_s: the runs per second
}

// Missions (docs/tasks.md): each stage's visit knot, its window and dwell, and its margin on the
// plan (eps-robust) and on the certified enclosures.
nlohmann::json mission_stages_json(const SolveOutcome& o, int horizon) {
  using nlohmann::json;
  const auto& c = o.certification;
  json stages = json::array();
  const planning::MissionSchedule initial = planning::schedule_missions(o.problem, horizon);
  for (const auto& p : o.plan.check.stages) {
    const AgentSpec& a = o.problem.agents[static_cast<std::size_t>(p.agent)];
    const MissionStage& st = a.stages[static_cast<std::size_t>(p.stage)];
    auto names = [&](const std::vector<int>& obs) {
      json n = json::array();
      for (int ob : obs) n.push_back(o.problem.obstacles[static_cast<std::size_t>(ob)].name);
      return n;
    };
    json cert = nullptr;
    for (const auto& q : c.stages)
      if (q.agent == p.agent && q.stage == p.stage && o.certification_ran)
        cert = {{"margin", q.margin}, {"at_samples", q.sampled_margin}, {"between_samples", margin_json(q.between_margin)}};
    stages.push_back({{"agent", a.name},
                      {"stage", st.name},
                      {"order", p.stage + 1},
                      {"region", st.is_polygon() ? "polygon" : "box"},
                      {"team", st.team.empty() ? json(nullptr) : json(st.team)},
                      {"visit_step", p.step},
                      {"visit_time_s", p.step * o.problem.tau},
                      // The distance-proportional first guess the plan started from.
                      {"initial_visit_step", initial.visit[static_cast<std::size_t>(p.agent)][static_cast<std::size_t>(p.stage)]},
                      {"dwell", p.dwell},
                      {"not_before", st.not_before},
                      {"by", st.by >= 0 ? json(st.by) : json(nullptr)},
                      {"avoid", names(st.avoid)},
                      {"avoid_after", names(st.avoid_after)},
                      {"plan_margin", p.margin},
                      {"plan_margin_at_samples", p.sampled_margin},
                      {"plan_margin_between_samples", margin_json(p.between_margin)},
                      {"certified", cert}});
  }
  return stages;
}

// Staged obstacles: where each binds each agent, at the plan's visit knots.
nlohmann::json staged_obstacles_json(const SolveOutcome& o, int horizon) {
  using nlohmann::json;
  json staged = json::array();
  const planning::ObstacleWindows windows(o.problem, planning::schedule_or_initial(o.problem, o.plan.visits, horizon));
  for (std::size_t ob = 0; ob < o.problem.obstacles.size(); ++ob)
    if (o.problem.obstacles[ob].staged)
      for (std::size_t i = 0; i < o.problem.agents.size(); ++i) {
        const std::vector<int> k = windows.knots(static_cast<int>(i), static_cast<int>(ob));
        if (k.empty()) continue;
        staged.push_back({{"obstacle", o.problem.obstacles[ob].name},
                          {"agent", o.problem.agents[i].name},
                          {"steps", windows.describe(static_cast<int>(i), static_cast<int>(ob))}});
      }
  return staged;
}

nlohmann::json mission_json(const SolveOutcome& o) {
  using nlohmann::json;
  const auto& c = o.certification;
  const int horizon = o.plan.horizon > 0 ? o.plan.horizon : o.problem.horizon;
  return {{"stages", mission_stages_json(o, horizon)},
          {"staged_obstacles", staged_obstacles_json(o, horizon)},
          {"certification", o.certification_ran && std::isfinite(c.stage.margin) ? certified_part_json(c.stage) : json(nullptr)},
          {"verification_between_samples", margin_json(o.verification.between.stage)}};
}

nlohmann::json attempts_json(const std::vector<Attempt>& attempts) {
  using nlohmann::json;
  json att = json::array();
  for (const auto& a : attempts)
    att.push_back({{"stage", a.stage},
                   {"parameters", a.parameters},
                   {"horizon", a.horizon > 0 ? json(a.horizon) : json(nullptr)},
                   {"outcome", a.outcome},
                   {"time_s", a.time_s}});
  return att;
}

}  // namespace

std::string auto_search_note(const SolveOutcome& o, std::size_t i) {
  if (i < o.auto_notes.size() && !o.auto_notes[i].empty()) return o.auto_notes[i];
  // Before: "the first value stood" after four rounds of eps x 0.8 (tests/problems/users2/01).
  int rounds = 0;
  for (const auto& r : o.search.rounds) {
    if (r.undone) continue;  // rolled back: not what the result used
    bool changed = false;
    for (const auto& c : r.changes)
      changed = changed || (c.what == "eps" && (c.agent.empty() || (i < o.problem.agents.size() && c.agent == o.problem.agents[i].name)));
    rounds += changed ? 1 : 0;
  }
  if (rounds > 0)
    return "the search's levers changed it in " + std::to_string(rounds) + " round" + (rounds == 1 ? "" : "s") + " (search: rounds)";
  return "the first value stood";
}

nlohmann::json result_json(const SolveOutcome& o) {
  using nlohmann::json;
  json j;
  // stopped: a signal or the time limit ended the search part-way; partial: controllers of some
  // agents are in the folder, each sound for its own tube, none for the team's specification.
  j["status"] = o.verified ? "verified" : o.search.interrupted ? "stopped" : "failed";
  if (!o.verified)
    j["partial"] = std::any_of(o.agents.begin(), o.agents.end(), [](const AgentOutcome& a) { return !a.controller_file.empty(); });
  if (!o.failure.empty()) j["failure"] = o.failure;
  j["problem"] = o.problem.name;
  // Which times the result holds for: every t in [0, T tau], or only t = k tau.
  j["guarantee"] = to_string(o.problem.guarantee);
  // The clearances the verdict is about (the file's delta, resolved): agent-agent, agent-obstacle
  // and agent-bound, in the norm of delta_norm.
  j["delta"] = {{"agents", o.problem.delta},
                {"obstacles", o.problem.obstacle_delta()},
                {"bounds", o.problem.delta_bounds},
                {"norm", o.problem.delta_norm == Norm::Inf ? "inf" : "2"}};
  j["tracker"] = o.problem.tracker.name;  // the request: a tracker or "auto"; each agent's is agents[i].tracker.name
  j["plan"] = plan_json(o);
  json agents = json::array();
  for (std::size_t i = 0; i < o.problem.agents.size(); ++i) agents.push_back(agent_json(o, i));
  j["agents"] = agents;
  j["certification"] = certification_json(o);
  j["verification"] = verification_json(o);
  if (std::any_of(o.problem.agents.begin(), o.problem.agents.end(), [](const AgentSpec& a) { return !a.stages.empty(); }))
    j["mission"] = mission_json(o);
  const auto& v = o.verification;
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
  j["attempts"] = attempts_json(o.attempts);
  j["search"] = search_json(o.search);
  j["tracking_time_s"] = o.search.track_time_s;  // every round's tracking, wall time
  // Bytes each stage added to the process at its peak (over all its rounds; absent: not run).
  nlohmann::json mem = nlohmann::json::object();
  auto stage = [&](const char* key, const StagePeak& p) {
    if (p.peak_bytes > 0) mem[key] = {{"added_bytes", p.added_bytes()}, {"peak_bytes", p.peak_bytes}, {"start_bytes", p.start_bytes}};
  };
  stage("plan", o.memory.plan);
  stage("tracking", o.memory.track);
  stage("certification", o.memory.certify);
  stage("verification", o.memory.verify);
  if (o.memory.plan_predicted_bytes > 0) mem["plan_predicted_bytes"] = o.memory.plan_predicted_bytes;
  if (o.memory.track_predicted_bytes > 0) mem["tracking_predicted_bytes"] = o.memory.track_predicted_bytes;
  if (o.memory.verify_predicted_bytes > 0) mem["verification_predicted_bytes"] = o.memory.verify_predicted_bytes;
  j["memory"] = mem;
  j["total_time_s"] = o.total_time_s;
  return j;
}

}  // namespace marsyn
