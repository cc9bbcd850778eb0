#include "marsyn/core/search_levers.hpp"

#include <sstream>
#include <variant>

#include "marsyn/core/problem/agent_checks.hpp"

namespace marsyn::search {
std::string vector_text(const Eigen::VectorXd& v) {
  std::ostringstream s;
  s << "(";
  for (Eigen::Index i = 0; i < v.size(); ++i) s << (i ? "," : "") << v[i];
  return s.str() + ")";
}

namespace {

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

// The changes between an agent before and after a lever, field by field.
void describe(const AgentSpec& before, const AgentSpec& after, std::vector<SearchChange>& out) {
  auto differ = [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return a.size() != b.size() || a != b; };
  if (before.tracker.name != after.tracker.name) out.push_back({after.name, "tracker", before.tracker.name, after.tracker.name});
  else if (params_text(before.tracker.params) != params_text(after.tracker.params))
    out.push_back({after.name, "tracker params", params_text(before.tracker.params), params_text(after.tracker.params)});
  if (differ(before.tube.eps, after.tube.eps)) out.push_back({after.name, "eps", vector_text(before.tube.eps), vector_text(after.tube.eps)});
  if (differ(before.tube.eta_x, after.tube.eta_x))
    out.push_back({after.name, "eta_x", vector_text(before.tube.eta_x), vector_text(after.tube.eta_x)});
  if (differ(before.tube.eta_u, after.tube.eta_u))
    out.push_back({after.name, "eta_u", vector_text(before.tube.eta_u), vector_text(after.tube.eta_u)});
}

}  // namespace

const char* lever_name(Lever lever) {
  switch (lever) {
    case Lever::ShrinkEps: return "shrink eps by 0.8 and re-plan";
    case Lever::FallBack: return "fall back to the next tracker (tracker: auto)";
    case Lever::Refine: return "refine the tracker";
    case Lever::EnlargeEps: return "enlarge eps by 1.25 and re-plan";
    case Lever::MoreClearance: return "re-plan with more clearance where certification fell short";
  }
  return "?";
}

int lever_cap(Lever lever) {
  switch (lever) {
    case Lever::ShrinkEps: return 4;
    case Lever::FallBack: return 1000;  // bounded by the installed trackers
    case Lever::Refine: return 4;
    case Lever::EnlargeEps: return 3;
    case Lever::MoreClearance: return 4;
  }
  return 0;
}

std::vector<Lever> levers_for(const Failure& f) {
  switch (f.kind) {
    case Failure::Plan: return {Lever::ShrinkEps};
    // The same eps first (another tracker, then the tracker's own knobs: the plan stays valid),
    // a wider tube last.
    case Failure::NoController: return {Lever::FallBack, Lever::Refine, Lever::EnlargeEps};
    case Failure::Certification: return {Lever::MoreClearance};
    default: return {};
  }
}

Proposal propose(Lever lever, const Failure& failure, const Team& team, TrackerInstances& instances,
                 const AssessRequest& request) {
  Proposal p;
  p.lever = lever;
  p.agents = team.problem->agents;
  p.trackers = *team.trackers;
  p.extra = *team.extra;
  auto acceptable = [&](const AgentSpec& a) {
    return agent_consistent(a) && assess_tracker(instances, a.tracker, a, request).ok;
  };
  auto consider = [&](int i, const AgentSpec& b) {
    if (!acceptable(b)) return;
    describe(p.agents[i], b, p.changes);
    p.agents[i] = b;
    p.changed.push_back(i);
  };
  // eps times `factor` for the agents `who`; a smaller tube keeps a grid no coarser than itself.
  auto scale_eps = [&](const std::vector<int>& who, double factor) {
    for (int i : who) {
      AgentSpec b = p.agents[i];
      b.tube.eps *= factor;
      if (factor < 1 && b.tube.eta_x.size() == b.tube.eps.size()) b.tube.eta_x = b.tube.eta_x.cwiseMin(b.tube.eps);
      consider(i, b);
    }
    p.replan = true;
  };
  std::vector<int> everyone(p.agents.size());
  for (std::size_t i = 0; i < everyone.size(); ++i) everyone[i] = static_cast<int>(i);
  switch (lever) {
    case Lever::ShrinkEps:
      scale_eps(everyone, 0.8);
      if (p.changed.empty()) p.why_not = "no agent's tracker accepts a smaller eps";
      break;
    case Lever::EnlargeEps:
      scale_eps(failure.agents, 1.25);
      if (p.changed.empty()) p.why_not = "a wider tube is refused by the goal, the state bounds or the tracker";
      break;
    case Lever::Refine:
      for (int i : failure.agents) {
        AgentSpec b = p.agents[i];
        if (instances.get(b.tracker)->refine(b)) consider(i, b);
      }
      if (p.changed.empty()) p.why_not = "the trackers have nothing left to refine";
      break;
    case Lever::FallBack:
      for (int i : failure.agents) {
        AgentTrackers& choice = p.trackers[i];
        while (choice.automatic && !choice.fallbacks.empty()) {
          AgentSpec b = p.agents[i];
          b.tracker = choice.fallbacks.front();
          choice.fallbacks.erase(choice.fallbacks.begin());
          const TrackerAssessment as = assess_tracker(instances, b.tracker, b, request);
          if (!as.ok) continue;
          choice.assessment = as;
          describe(p.agents[i], b, p.changes);
          p.agents[i] = b;
          p.changed.push_back(i);
          break;
        }
      }
      if (p.changed.empty()) {
        bool automatic = false;
        for (int i : failure.agents) automatic = automatic || p.trackers[i].automatic;
        p.why_not = automatic ? "no other installed tracker accepts the agents"
                              : "the file names the agents' trackers; only tracker: auto falls back";
      }
      break;
    case Lever::MoreClearance:
      // Remark 2 between the samples: 1.5 times the shortfall, exactly where the period enclosures
      // came too close.
      for (const auto& [name, m] : failure.shortfalls) {
        const double before = p.extra.count(name) ? p.extra.at(name) : 0.0;
        p.extra[name] = before + 1.5 * -m;
        p.changes.push_back({"", "clearance of " + name, std::to_string(before), std::to_string(p.extra[name])});
      }
      p.replan = true;
      if (p.changes.empty()) p.why_not = "certification named no requirement to clear";
      break;
  }
  return p;
}

void apply(const Proposal& p, const Team& team) {
  team.problem->agents = p.agents;
  *team.trackers = p.trackers;
  *team.extra = p.extra;
}

std::string fingerprint(const std::vector<AgentSpec>& agents, const std::map<std::string, double>& extra) {
  std::ostringstream s;
  s.precision(12);  // eps x 0.8 x 1.25 is the same tube, whatever the last bits say
  auto put = [&](const Eigen::VectorXd& v) {
    for (Eigen::Index i = 0; i < v.size(); ++i) s << v[i] << ",";
    s << ";";
  };
  for (const auto& a : agents) {
    s << a.name << ":" << a.tracker.name << params_text(a.tracker.params) << ":";
    put(a.tube.eps);
    put(a.tube.eta_x);
    put(a.tube.eta_u);
  }
  for (const auto& [name, v] : extra) s << name << "=" << v << ";";
  return s.str();
}

}  // namespace marsyn::search
