#include "marsyn/core/verification/certification.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <sstream>

#include "marsyn/core/planning/box_margins.hpp"
#include "marsyn/core/planning/constraints.hpp"
#include "marsyn/stopwatch.hpp"
#include "marsyn/number_text.hpp"

namespace marsyn {

namespace {

// Record a margin in a part; names are built only for new minima.
void record(CertifiedPart& part, double margin, int step, const std::function<std::string()>& where,
            std::map<std::string, double>& shortfalls) {
  if (!(margin >= part.margin)) {
    part.margin = std::isnan(margin) ? -std::numeric_limits<double>::infinity() : margin;
    part.step = step;
    part.where = where();
  }
  if (!(margin >= 0)) {
    auto [it, fresh] = shortfalls.try_emplace(where(), margin);
    if (!fresh) it->second = std::min(it->second, margin);
  }
}

// Per agent and step: its enclosures in time order.
using ByStep = std::vector<std::vector<std::vector<const PeriodEnclosure*>>>;

// Body slot b's workspace box over an enclosure of its agent: the tracker's own for the first
// body; for a further one, the body's map over the enclosure's state box (it holds every state of
// that part, so the image holds every point of the body).
Box body_workspace(const Problem& pb, int b, const PeriodEnclosure& e) {
  if (b < static_cast<int>(pb.agents.size())) return e.workspace;
  return planning::workspace_box(pb.body_spec(b), e.state);
}

// A margin below 0 fails its agents.
void note(std::set<int>& failing, double margin, std::initializer_list<int> agents) {
  if (!(margin >= 0))
    for (int a : agents) failing.insert(a);
}

// Indexes every controller's enclosures by step (into by_step, the horizon into T); false, with
// r.message (and the agent at fault), when the controllers give no continuous-time guarantee
// this check can read.
bool index_enclosures(const Problem& pb, const std::vector<std::shared_ptr<const Controller>>& ctrls, ByStep& by_step,
                      int& T, CertificationReport& r) {
  const int N = static_cast<int>(pb.agents.size());
  for (int i = 0; i < N; ++i) {
    if (!ctrls[i]) {
      r.message = "not certified: agent " + pb.agents[i].name + " has no controller";
      return false;
    }
    const int Ti = ctrls[i]->horizon();
    if (T < 0) T = Ti;
    if (Ti != T || Ti < 0) {
      r.message = "not certified: the agents' controllers have different horizons";
      return false;
    }
    by_step[i].assign(static_cast<size_t>(T), {});
    for (const PeriodEnclosure& e : ctrls[i]->period_enclosures())
      if (e.step >= 0 && e.step < T) by_step[i][static_cast<size_t>(e.step)].push_back(&e);
    for (int k = 0; k < T; ++k) {
      auto& v = by_step[i][static_cast<size_t>(k)];
      if (v.empty()) {
        r.message = "not certified: the controller of " + pb.agents[i].name + " has no enclosure between samples " +
                    std::to_string(k) + " and " + std::to_string(k + 1) +
                    " (the tracker gives no continuous-time guarantee)";
        r.failing_agents.push_back(i);
        return false;
      }
      std::sort(v.begin(), v.end(), [](const PeriodEnclosure* a, const PeriodEnclosure* b) { return a->t0 < b->t0; });
      // Parts are compared by index below, which needs the tracker's split of the period into
      // equal parts (tracker.hpp): refuse anything else rather than assume it.
      const double n = static_cast<double>(v.size()), tol = 1e-9 * pb.tau;
      for (size_t p = 0; p < v.size(); ++p) {
        const double t0 = pb.tau * (k + p / n), t1 = pb.tau * (k + (p + 1) / n);
        if (!(std::abs(v[p]->t0 - t0) <= tol && std::abs(v[p]->t1 - t1) <= tol)) {
          r.message = "not certified: the enclosures of " + pb.agents[i].name + " between samples " +
                      std::to_string(k) + " and " + std::to_string(k + 1) +
                      " do not split the period into equal parts covering it";
          r.failing_agents.push_back(i);
          return false;
        }
      }
      r.enclosures += static_cast<long long>(v.size());
    }
  }
  return true;
}

// Each agent alone: its state bounds and the obstacles.
void certify_agents(const Problem& pb, const ByStep& by_step, int T, CertificationReport& r, std::set<int>& failing) {
  const planning::ObstacleWindows windows(pb, T);
  for (int i = 0; i < static_cast<int>(pb.agents.size()); ++i) {
    const auto& a = pb.agents[i];
    for (int k = 0; k < T; ++k)
      for (const PeriodEnclosure* e : by_step[i][static_cast<size_t>(k)])
        for (int c = 0; c < a.state_bounds.dim(); ++c) {
          const double mb = planning::box_inside_margin(e->state, a.state_bounds, c);
          record(r.state_bounds, mb, k, [&] { return planning::state_bound_name(a, c); }, r.shortfalls);
          note(failing, mb, {i});
        }
  }
  for (int b = 0; b < pb.body_count(); ++b) {
    const int i = pb.body_agent(b);
    const double clearance = planning::obstacle_clearance_up(pb, b);
    for (int k = 0; k < T; ++k)
      for (const PeriodEnclosure* e : by_step[i][static_cast<size_t>(k)]) {
        const Box w = body_workspace(pb, b, *e);
        for (size_t o = 0; o < pb.obstacles.size(); ++o) {
          if (!windows.binds(i, static_cast<int>(o), {k, true})) continue;
          const double mo = planning::box_obstacle_margin(w, pb.obstacles[o], clearance, pb.delta_norm);
          record(r.obstacle, mo, k, [&] { return planning::obstacle_name(pb, static_cast<int>(o), pb.body_spec(b)); },
                 r.shortfalls);
          note(failing, mo, {i});
        }
      }
  }
}

// Part p of n parts covers [p/n, (p+1)/n] of the period (the trackers split it evenly, in real
// arithmetic); two parts are compared when their open time intervals meet: at any t some
// such pair holds both agents' states.
void overlapping(const ByStep& by_step, int i, int j, int k,
                 const std::function<void(const PeriodEnclosure&, const PeriodEnclosure&)>& fn) {
  const auto& A = by_step[i][static_cast<size_t>(k)];
  const auto& B = by_step[j][static_cast<size_t>(k)];
  const long long na = static_cast<long long>(A.size()), nb = static_cast<long long>(B.size());
  for (long long p = 0; p < na; ++p)
    for (long long q = 0; q < nb; ++q)
      if (p * nb < (q + 1) * na && q * na < (p + 1) * nb) fn(*A[static_cast<size_t>(p)], *B[static_cast<size_t>(q)]);
}

// Pairs of agents: collisions and the formation.
void certify_pairs(const Problem& pb, const ByStep& by_step, int T, CertificationReport& r, std::set<int>& failing) {
  const int B = pb.body_count(), N = static_cast<int>(pb.agents.size());
  // Body slots s < t of two agents (each agent's first bodies are slots 0..N-1: two agents
  // without further bodies are compared on the trackers' own workspace boxes).
  if (pb.pairwise_collision)
    for (int s = 0; s < B; ++s)
      for (int t = s + 1; t < B; ++t) {
        const int i = pb.body_agent(s), j = pb.body_agent(t);
        if (i == j) continue;
        const double clearance = planning::pair_clearance_up(pb, s, t);
        for (int k = 0; k < T; ++k)
          overlapping(by_step, i, j, k, [&](const PeriodEnclosure& ea, const PeriodEnclosure& eb) {
            const double m = s < N && t < N ? planning::box_pair_margin(ea.workspace, eb.workspace, clearance, pb.delta_norm)
                                            : planning::box_pair_margin(body_workspace(pb, s, ea), body_workspace(pb, t, eb),
                                                                        clearance, pb.delta_norm);
            record(r.collision, m, k, [&] { return planning::collision_name(pb.body_spec(s), pb.body_spec(t)); },
                   r.shortfalls);
            note(failing, m, {i, j});
          });
      }
  for (const auto& f : pb.formation)
    for (int k = 0; k < T; ++k)
      overlapping(by_step, f.i, f.j, k, [&](const PeriodEnclosure& ea, const PeriodEnclosure& eb) {
        const double m = planning::box_formation_margin(ea.workspace, eb.workspace, f.lambda, f.mu);
        record(r.formation, m, k, [&] { return planning::formation_name(pb.agents[f.i], pb.agents[f.j]); },
               r.shortfalls);
        note(failing, m, {f.i, f.j});
      });
}

// Mission stages: the state at knot k lies in the part starting at k tau and in the part
// ending there; their intersection encloses it.
void certify_stages(const Problem& pb, const ByStep& by_step, int T, CertificationReport& r, std::set<int>& failing) {
  const planning::MissionSchedule sched = planning::schedule_missions(pb, T);
  if (!sched.feasible)
    record(r.stage, -std::numeric_limits<double>::infinity(), T, [&] { return "mission schedule: " + sched.why; },
           r.shortfalls);
  r.stages = planning::stage_visits(pb, T);
  for (auto& v : r.stages) {
    const auto& a = pb.agents[v.agent];
    const auto& st = a.stages[v.stage];
    const auto& steps = by_step[v.agent];
    v.sampled_margin = std::numeric_limits<double>::infinity();
    for (int k = v.step; k <= std::min(T, v.step + v.dwell); ++k) {
      const PeriodEnclosure* after = k < T ? steps[static_cast<size_t>(k)].front() : nullptr;
      const PeriodEnclosure* before = k > 0 ? steps[static_cast<size_t>(k - 1)].back() : nullptr;
      Box state = (after ? after : before)->state, ws = (after ? after : before)->workspace;
      if (after && before) {
        state = {state.lo.cwiseMax(before->state.lo), state.hi.cwiseMin(before->state.hi)};
        ws = {ws.lo.cwiseMax(before->workspace.lo), ws.hi.cwiseMin(before->workspace.hi)};
      }
      v.sampled_margin = std::min(v.sampled_margin, planning::stage_margin(st, state, ws));
    }
    for (int k = v.step; k < std::min(T, v.step + v.dwell); ++k)
      for (const PeriodEnclosure* e : steps[static_cast<size_t>(k)])
        v.between_margin = std::min(v.between_margin, planning::stage_margin(st, e->state, e->workspace));
    v.margin = std::min(v.sampled_margin, v.between_margin);
    record(r.stage, v.margin, v.step, [&] { return v.name; }, r.shortfalls);
    note(failing, v.margin, {v.agent});
  }
}

}  // namespace

CertificationReport certify(const Problem& pb, const std::vector<std::shared_ptr<const Controller>>& ctrls) {
  const Stopwatch clock;
  CertificationReport r;
  const int N = static_cast<int>(pb.agents.size());
  if (static_cast<int>(ctrls.size()) != N) {
    r.message = "not certified: one controller per agent is needed";
    return r;
  }
  int T = -1;
  ByStep by_step(N);
  if (!index_enclosures(pb, ctrls, by_step, T, r)) return r;
  std::set<int> failing;
  certify_agents(pb, by_step, T, r, failing);
  certify_pairs(pb, by_step, T, r, failing);
  if (std::any_of(pb.agents.begin(), pb.agents.end(), [](const AgentSpec& a) { return !a.stages.empty(); }))
    certify_stages(pb, by_step, T, r, failing);

  const CertifiedPart* worst = nullptr;
  for (const CertifiedPart* p : {&r.state_bounds, &r.obstacle, &r.collision, &r.formation, &r.stage})
    if (!worst || p->margin < worst->margin) worst = p;
  r.min_margin = worst->margin;
  r.failing_agents.assign(failing.begin(), failing.end());
  r.certified = r.min_margin >= 0;
  std::ostringstream os;
  os.precision(kMessageDigits);
  os << (r.certified ? "certified in continuous time" : "NOT certified in continuous time") << ": " << r.enclosures
     << " period enclosures, smallest margin " << number_text(r.min_margin);
  if (worst->step >= 0)
    os << " (" << worst->where << " between steps " << worst->step << " and " << worst->step + 1 << ")";
  r.message = os.str();
  r.time_s = clock.seconds();
  return r;
}

}  // namespace marsyn
