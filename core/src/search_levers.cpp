#include "marsyn/core/search_levers.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <variant>

#include "marsyn/core/planning/goal_room.hpp"
#include "marsyn/core/planning/workspace_gaps.hpp"
#include "marsyn/core/problem/agent_checks.hpp"
#include "marsyn/core/problem/tracker_fields.hpp"
#include "marsyn/number_text.hpp"

namespace marsyn::search {
std::string vector_text(const Eigen::VectorXd& v) { return list_text(v, "(", ")", ","); }

std::string params_text(const Params& p) {
  std::ostringstream s;
  s.precision(17);
  s << "{";
  bool first = true;
  for (const auto& [name, value] : p.values()) {
    s << (first ? "" : ", ") << name << ": ";
    first = false;
    std::visit(
        [&](const auto& v) {
          using T = std::decay_t<decltype(v)>;
          if constexpr (std::is_same_v<T, std::vector<double>>) {
            s << "[";
            for (std::size_t i = 0; i < v.size(); ++i) s << (i ? ", " : "") << v[i];
            s << "]";
          } else {
            s << v;
          }
        },
        value);
  }
  return s.str() + "}";
}

void describe(const AgentSpec& before, const AgentSpec& after, std::vector<SearchChange>& out) {
  auto differ = [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return a.size() != b.size() || a != b; };
  if (before.tracker.name != after.tracker.name) out.push_back({after.name, "tracker", before.tracker.name, after.tracker.name});
  else if (params_text(before.tracker.params) != params_text(after.tracker.params))
    out.push_back({after.name, "tracker params", params_text(before.tracker.params), params_text(after.tracker.params)});
  if (differ(before.tube.eps, after.tube.eps)) out.push_back({after.name, "eps", vector_text(before.tube.eps), vector_text(after.tube.eps)});
  // The trackers' own fields (abcd's grid), by name.
  for (const auto& f : after.fields.items)
    if (const Eigen::VectorXd was = before.fields.value(f.name); differ(was, f.value))
      out.push_back({after.name, f.name, vector_text(was), vector_text(f.value)});
}

std::string lever_name(const LeverChoice& l) {
  switch (l.lever) {
    case Lever::LongerHorizon: return "plan from a longer horizon";
    case Lever::ShrinkEps: return "shrink eps (x 0.8 or less) and re-plan";
    case Lever::TightenInput: return "re-plan with U tightened for the nominal";
    case Lever::TrackerLever: return "the tracker's " + l.tracker_lever;
    case Lever::EpsInCoordinate: return "enlarge eps by 1.25 in the missed coordinate and re-plan";
    case Lever::FallBack: return "fall back to the next tracker (tracker: auto)";
    case Lever::EnlargeEps: return "enlarge eps by 1.25 and re-plan";
    case Lever::MoreClearance: return "re-plan with more clearance where certification fell short";
    case Lever::WidenForMiss: return "widen eps by the small miss (its coordinate and those at the edge; the plan re-checked)";
  }
  return "?";
}

int lever_cap(Lever lever) {
  switch (lever) {
    case Lever::LongerHorizon: return 1;
    case Lever::ShrinkEps: return 4;
    case Lever::TightenInput: return 2 * kInputShareLevels;  // per agent: kInputShareLevels
    case Lever::TrackerLever: return 4;
    case Lever::EpsInCoordinate: return 3;
    case Lever::FallBack: return 1000;  // bounded by the installed trackers
    case Lever::EnlargeEps: return 3;
    case Lever::MoreClearance: return 4;
    case Lever::WidenForMiss: return 4;  // per agent
  }
  return 0;
}

double widened_eps(double eps, double amount) { return eps + kMissFactor * amount + kMissMargin * eps; }

bool small_miss(const Failure& f, std::size_t w) {
  return w < f.miss_share.size() && f.miss_share[w] > 0 && f.miss_share[w] <= kSmallMiss;
}

double input_share_after(int uses) { return 1.0 - 0.2 * uses; }

double next_input_share(double share) {
  for (int uses = 1; uses <= kInputShareLevels; ++uses)
    if (input_share_after(uses) < share - 1e-9) return input_share_after(uses);
  return share;
}

std::vector<LeverChoice> levers_for(const Failure& f, const std::vector<TrackerLever>& declared) {
  switch (f.kind) {
    // The planning stage lengthened the horizon already: longer still, then a narrower tube.
    // Starts too crowded for the tubes (planning/workspace_gaps.hpp): no horizon can help.
    case Failure::Plan:
      // Neither a longer horizon nor a narrower tube: nothing the search can change helps.
      if (!f.horizon_blocked.empty() && f.beyond_eps) return {};
      if (f.start_eps_factor < 1 || f.formation_eps_factor < 1 || f.goal_eps_factor < 1 || f.gap_eps_factor < 1 ||
          !f.horizon_blocked.empty())
        return {{Lever::ShrinkEps, ""}};
      return {{Lever::LongerHorizon, ""}, {Lever::ShrinkEps, ""}};
    case Failure::Certification: return {{Lever::MoreClearance, ""}};
    case Failure::NoController: break;
    default: return {};
  }
  std::vector<LeverChoice> out;
  // A miss of a few per cent of eps: the tracker all but succeeded; a tube that much wider,
  // checked on the existing plan, is the cheapest round there is (no re-plan, no knob).
  if (small_miss(f, 0)) out.push_back({Lever::WidenForMiss, ""});
  // The levers that keep the plan come first (the failed agents' trackers' own knobs, another
  // tracker for just those agents): they leave every other agent's plan and controller as it is.
  // A re-plan perturbs every agent's nominal and can break controllers elsewhere, so it waits.
  // The first failed agent's reason decides the order (the others' levers follow it).
  const TrackFailureKind kind = f.why.empty() ? TrackFailureKind::Unknown : f.why.front().kind;
  auto own = [&] {
    for (const auto& l : declared)
      for (TrackFailureKind k : l.addresses)
        if (k == kind) {
          out.push_back({Lever::TrackerLever, l.name});
          break;
        }
  };
  // A nominal pinned at a bound of U leaves the feedback no authority there (the torque-limited
  // swing-up): when no knob of the tracker gave it back, a plan inside a smaller U does.
  bool pinned = false;
  for (std::size_t i = 0; i < f.agents.size(); ++i)
    pinned = pinned || (i < f.nominal_saturation.size() && f.nominal_saturation[i] > 0) ||
             (i < f.why.size() && f.why[i].input_saturation > 0);
  // A miss whose enclosure is narrow but off the nominal, with inputs at a bound: the tracker's
  // knobs tighten the enclosure, which is not what failed; the re-plan inside a smaller U goes
  // first (measured on tests/problems/17: 10 rounds and 204 s with the knobs first).
  const bool off_centre_first = kind == TrackFailureKind::TubeMiss && pinned && f.why.front().off_centre;
  if (off_centre_first) out.push_back({Lever::TightenInput, ""});
  switch (kind) {
    case TrackFailureKind::TubeMiss:
    case TrackFailureKind::EmptyWinningSet:
      own();
      out.push_back({Lever::FallBack, ""});
      break;
    case TrackFailureKind::Unknown:
      // The same eps first (another tracker, then the tracker's own knobs: the plan stays valid).
      out.push_back({Lever::FallBack, ""});
      own();
      break;
  }
  if (pinned && !off_centre_first) out.push_back({Lever::TightenInput, ""});
  if (kind == TrackFailureKind::TubeMiss) out.push_back({Lever::EpsInCoordinate, ""});
  out.push_back({Lever::EnlargeEps, ""});
  return out;
}

namespace {

// One proposal in the making: the copy it changes, and why each refused change was refused,
// for the stop message ("a1: eps[theta] 0.156 empties the goal ..."): the first reason per agent.
class Proposer {
 public:
  Proposer(const LeverChoice& lever, const Failure& failure, const Team& team, TrackerInstances& instances,
           const AssessRequest& request)
      : lever_(lever), failure_(failure), team_(team), instances_(instances), request_(request), p_(unchanged(team)) {
    p_.lever = lever;
  }

  Proposal run() {
    switch (lever_.lever) {
      case Lever::LongerHorizon: longer_horizon(); break;
      case Lever::ShrinkEps: shrink_eps(); break;
      case Lever::EnlargeEps:
        scale_eps(failure_.agents, 1.25, {});
        if (p_.changed.empty()) p_.why_not = "a wider tube is refused" + refusals();
        break;
      case Lever::EpsInCoordinate: eps_in_coordinate(); break;
      case Lever::TightenInput: tighten_input(); break;
      case Lever::TrackerLever: tracker_lever(); break;
      case Lever::FallBack: fall_back(); break;
      case Lever::MoreClearance: more_clearance(); break;
      case Lever::WidenForMiss: widen_for_miss(); break;
    }
    return p_;
  }

 private:
  bool acceptable(const AgentSpec& a) {
    const std::string defect = agent_defect_text(a);
    if (!defect.empty()) {
      refused_.push_back(a.name + ": " + defect);
      return false;
    }
    const TrackerAssessment as = assess_tracker(instances_, a.tracker, a, request_);
    if (!as.ok) refused_.push_back(a.name + ": " + a.tracker.name + " refuses (" + as.message + ")");
    return as.ok;
  }

  std::string refusals() const {
    std::string out;
    for (std::size_t r = 0; r < refused_.size() && r < 3; ++r) out += (r ? "; " : ": ") + refused_[r];
    if (refused_.size() > 3) out += "; and " + std::to_string(refused_.size() - 3) + " more";
    return out;
  }

  void consider(int i, const AgentSpec& b) {
    if (!acceptable(b)) return;
    describe(p_.agents[i], b, p_.changes);
    p_.agents[i] = b;
    p_.changed.push_back(i);
  }

  // eps times `factor` for the agents `who` (in coordinate `only`, or all when -1); the trackers
  // keep their fields within a smaller tube (abcd: a grid no coarser than it).
  void scale_eps(const std::vector<int>& who, double factor, const std::vector<int>& only) {
    for (std::size_t w = 0; w < who.size(); ++w) {
      const int i = who[w];
      AgentSpec b = p_.agents[i];
      const int c = w < only.size() ? only[w] : -1;
      if (c >= 0 && c < b.n()) b.tube.eps[c] *= factor;
      else if (c < 0) b.tube.eps *= factor;
      else continue;
      if (factor < 1) follow_tube(instances_, b, TubeChange::Narrowed);
      consider(i, b);
    }
    p_.replan = true;
    p_.recheck = factor > 1;  // a wider tube may leave the plan robust: the search checks it first
  }

  void widen_for_miss() {
    for (std::size_t w = 0; w < failure_.agents.size() && w < failure_.why.size(); ++w) {
      const TrackFailure& why = failure_.why[w];
      if (!small_miss(failure_, w) || why.coordinate < 0) continue;
      const int i = failure_.agents[w];
      AgentSpec b = p_.agents[i];
      if (why.coordinate >= b.n()) continue;
      const double was = b.tube.eps[why.coordinate];
      b.tube.eps[why.coordinate] = widened_eps(was, why.amount);
      const double factor = b.tube.eps[why.coordinate] / was;
      for (int c = 0; c < b.n() && c < static_cast<int>(why.tube_use.size()); ++c)
        if (c != why.coordinate && why.tube_use[static_cast<std::size_t>(c)] >= kNearEdge) b.tube.eps[c] *= factor;
      consider(i, b);
    }
    p_.replan = true;
    p_.recheck = true;
    if (p_.changed.empty()) p_.why_not = "no failed agent missed by a small share of eps, or the wider tube is refused" + refusals();
  }

  void longer_horizon() {
    const int from = std::max(failure_.longest_horizon, team_.problem->horizon);
    const int to = std::max(from + 1, static_cast<int>(std::ceil(from * 1.25)));
    if (from <= 0 || to > 100000) {
      p_.why_not = "no horizon to start from";
      return;
    }
    p_.min_horizon = to;
    p_.changes.push_back({"", "horizon", std::to_string(from), std::to_string(to)});
    p_.replan = true;
  }

  // 0.8, or further where crowded starts need it (just below the factor that makes step 0 robust)
  // or a formation's tolerance does (planning::formation_eps_factor).
  void shrink_eps() {
    const double start = planning::start_eps_factor(*team_.problem);
    const double formation = planning::formation_eps_factor(*team_.problem);
    const double goal = planning::goal_eps_factor(*team_.problem);
    if (start <= 0.05) {
      p_.why_not = "the starts are too close for any tube (eps x " + number_text(start, 3) + ")";
      return;
    }
    if (goal <= 0.05) {
      p_.why_not = "a goal leaves no room for any tube (eps x " + number_text(goal, 3) + ")";
      return;
    }
    std::vector<int> everyone(p_.agents.size());
    for (std::size_t i = 0; i < everyone.size(); ++i) everyone[i] = static_cast<int>(i);
    const double gap = failure_.gap_eps_factor;
    if (gap <= 0.05) {
      p_.why_not = "the gap the plan is pressed into stays closed for any tube (eps x " + number_text(gap, 3) + ")";
      return;
    }
    // Crowded starts alone: only the crowded agents narrow, each as far as its own starts need
    // (issue 51: one car beside a kerb narrowed the whole junction's tubes, the others' too).
    if (start < 1 && std::min({goal, formation, gap}) >= 1) {
      const std::vector<double> own = planning::start_eps_factors(*team_.problem);
      double least = 1.0;
      for (std::size_t i = 0; i < own.size() && i < p_.agents.size(); ++i)
        if (own[i] < 1) {
          const double f = std::min(0.8, 0.95 * own[i]);
          least = std::min(least, f);
          scale_eps({static_cast<int>(i)}, f, {});
        }
      std::string who;
      for (int i : p_.changed) who += (who.empty() ? "" : ", ") + p_.agents[static_cast<std::size_t>(i)].name;
      if (!p_.changed.empty())
        p_.changes.push_back({"", "eps factor", "0.8",
                              number_text(least, 3) + " or less (what the crowded starts need; " + who +
                                  " only, the other agents keep their eps)"});
      if (p_.changed.empty()) p_.why_not = "no crowded agent's tracker accepts a smaller eps" + refusals();
      return;
    }
    const double factor = std::min({0.8, 0.95 * start, 0.95 * goal, formation, gap});
    scale_eps(everyone, factor, {});
    const char* why = formation <= factor            ? " (what the formation's tolerance needs)"
                      : 0.95 * start <= factor       ? " (what the crowded starts need)"
                      : gap <= factor                ? " (what opens the gap the plan is pressed into)"
                                                     : " (what the goals without room need)";
    if (factor < 0.8 && !p_.changed.empty())  // the lever's name says 0.8: say why this round went further
      p_.changes.push_back({"", "eps factor", "0.8", number_text(factor, 3) + why});
    if (p_.changed.empty()) p_.why_not = "no agent's tracker accepts a smaller eps" + refusals();
  }

  void eps_in_coordinate() {
    std::vector<int> who, coord;
    for (std::size_t w = 0; w < failure_.agents.size() && w < failure_.why.size(); ++w)
      if (failure_.why[w].kind == TrackFailureKind::TubeMiss && failure_.why[w].coordinate >= 0) {
        who.push_back(failure_.agents[w]);
        coord.push_back(failure_.why[w].coordinate);
      }
    if (who.empty()) {
      p_.why_not = "no tracker named the coordinate it missed";
      return;
    }
    scale_eps(who, 1.25, coord);
    if (p_.changed.empty()) p_.why_not = "a wider tube in that coordinate is refused" + refusals();
  }

  // Per agent, one level at a time: an agent tightened for the first time starts at the mild
  // level (80 %), whatever other agents reached before.
  void tighten_input() {
    for (std::size_t w = 0; w < failure_.agents.size(); ++w) {
      const int i = failure_.agents[w];
      const bool pinned = (w < failure_.nominal_saturation.size() && failure_.nominal_saturation[w] > 0) ||
                          (w < failure_.why.size() && failure_.why[w].input_saturation > 0);
      const double share = next_input_share(p_.input_share[i]);
      if (!pinned || !(share < p_.input_share[i])) continue;
      char from[32], to[32];
      std::snprintf(from, sizeof from, "%.0f %%", 100 * p_.input_share[i]);
      std::snprintf(to, sizeof to, "%.0f %%", 100 * share);
      p_.changes.push_back({p_.agents[i].name, "share of U for the nominal", from, to});
      p_.input_share[i] = share;
      p_.changed.push_back(i);
    }
    if (p_.changes.empty()) p_.why_not = "no failed agent's nominal sits at a bound of U that can still be tightened";
    p_.replan = true;
  }

  void tracker_lever() {
    for (std::size_t w = 0; w < failure_.agents.size(); ++w) {
      const int i = failure_.agents[w];
      AgentSpec b = p_.agents[i];
      const TrackFailure why = w < failure_.why.size() ? failure_.why[w] : TrackFailure{};
      std::shared_ptr<const Tracker> t;
      try {
        t = instances_.get(b.tracker);
      } catch (const std::exception&) {
        continue;
      }
      if (t->apply_lever(lever_.tracker_lever, why, b)) consider(i, b);
    }
    if (p_.changed.empty()) p_.why_not = "no failed agent's tracker can turn it further";
  }

  void fall_back() {
    for (int i : failure_.agents) {
      AgentTrackers& choice = p_.trackers[i];
      while (choice.automatic && !choice.fallbacks.empty()) {
        AgentSpec b = p_.agents[i];
        b.tracker = choice.fallbacks.front();
        choice.fallbacks.erase(choice.fallbacks.begin());
        const TrackerAssessment as = assess_tracker(instances_, b.tracker, b, request_);
        if (!as.ok) {
          refused_.push_back(b.name + ": " + b.tracker.name + " refuses (" + as.message + ")");
          continue;
        }
        choice.assessment = as;
        describe(p_.agents[i], b, p_.changes);
        p_.agents[i] = b;
        p_.changed.push_back(i);
        break;
      }
    }
    if (p_.changed.empty()) {
      bool automatic = false;
      for (int i : failure_.agents) automatic = automatic || p_.trackers[i].automatic;
      // Every fallback used already (no refusal) is not the same as one that refused.
      p_.why_not = !automatic ? "the file names the agents' trackers; only tracker: auto falls back"
                   : refused_.empty() ? "the failed agents have tried every installed tracker that accepts them"
                                      : "no other installed tracker accepts the agents" + refusals();
    }
  }

  // Remark 2 between the samples: 1.5 times the shortfall, exactly where the period enclosures
  // came too close.
  void more_clearance() {
    for (const auto& [name, m] : failure_.shortfalls) {
      const double before = p_.extra.count(name) ? p_.extra.at(name) : 0.0;
      p_.extra[name] = before + 1.5 * -m;
      p_.changes.push_back({"", "clearance of " + name, number_text(before, 3), number_text(p_.extra[name], 3)});
    }
    p_.replan = true;
    if (p_.changes.empty()) p_.why_not = "certification named no requirement to clear";
  }

  const LeverChoice& lever_;
  const Failure& failure_;
  const Team& team_;
  TrackerInstances& instances_;
  const AssessRequest& request_;
  Proposal p_;
  std::vector<std::string> refused_;
};

}  // namespace

Proposal unchanged(const Team& team) {
  Proposal p;
  p.agents = team.problem->agents;
  p.trackers = *team.trackers;
  p.extra = *team.extra;
  p.input_share = *team.input_share;
  p.input_share.resize(p.agents.size(), 1.0);
  p.min_horizon = *team.min_horizon;
  return p;
}

Proposal propose(const LeverChoice& lever, const Failure& failure, const Team& team, TrackerInstances& instances,
                 const AssessRequest& request, int /*uses*/) {
  return Proposer(lever, failure, team, instances, request).run();
}

void apply(const Proposal& p, const Team& team) {
  team.problem->agents = p.agents;
  *team.trackers = p.trackers;
  *team.extra = p.extra;
  *team.input_share = p.input_share;
  *team.min_horizon = p.min_horizon;
}

std::string fingerprint(const std::vector<AgentSpec>& agents, const std::map<std::string, double>& extra,
                        const std::vector<double>& input_share, int min_horizon) {
  std::ostringstream s;
  s.precision(12);  // eps x 0.8 x 1.25 is the same tube, whatever the last bits say
  auto put = [&](const Eigen::VectorXd& v) {
    for (Eigen::Index i = 0; i < v.size(); ++i) s << v[i] << ",";
    s << ";";
  };
  for (const auto& a : agents) {
    s << a.name << ":" << a.tracker.name << params_text(a.tracker.params) << ":";
    put(a.tube.eps);
    for (const auto& f : a.fields.items) put(f.value);
  }
  for (const auto& [name, v] : extra) s << name << "=" << v << ";";
  for (std::size_t i = 0; i < input_share.size(); ++i)
    if (input_share[i] != 1.0) s << "U" << i << "=" << input_share[i] << ";";  // the file's U (share 1) prints nothing: fingerprints stay comparable
  s << "T>=" << min_horizon;
  return s.str();
}

}  // namespace marsyn::search
