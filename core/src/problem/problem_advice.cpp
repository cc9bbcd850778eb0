#include "marsyn/core/problem/problem_advice.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "marsyn/core/planning/workspace_gaps.hpp"
#include "marsyn/core/problem/tracker_fields.hpp"
#include "marsyn/memory_budget.hpp"
#include "marsyn/number_text.hpp"
#include "agent_runs.hpp"

namespace marsyn {

namespace {

// "42.5 s", above a minute "2.5 min": how long a tracker expects to take (4 digits; the search
// prints its own times as "%.3g s").
std::string seconds_or_minutes(double s) {
  if (s >= 60) return number_text(s / 60, 4) + " min";
  return number_text(s, 4) + " s";
}

std::string coordinate(const AgentSpec& a, int i) {
  const auto names = a.dynamics ? a.dynamics->state_names() : std::vector<std::string>{};
  return i < static_cast<int>(names.size()) ? "'" + names[i] + "'" : "coordinate " + std::to_string(i);
}


}  // namespace

Advice advise(const LoadedProblem& lp) {
  Advice out;
  const Problem& pb = lp.problem;
  TrackerInstances instances(lp.registry);
  const AssessRequest ask{pb.horizon, pb.tau, lp.memory_budget};
  const std::vector<std::string> installed = lp.registry->names("tracker");
  for (std::size_t i = 0; i < pb.agents.size(); ++i) {
    const AgentSpec& a = pb.agents[i];
    AgentAdvice ad;
    ad.agent = a.name;
    ad.chosen = a.tracker.name;
    if (i < lp.trackers.size()) {
      ad.automatic = lp.trackers[i].automatic;
      for (const auto& f : lp.trackers[i].fallbacks) ad.fallbacks.push_back(f.name);
    }
    for (const auto& name : installed) {
      // The agent's own tracker with its parameters, the others as installed.
      const PluginChoice choice = name == a.tracker.name ? a.tracker : PluginChoice{name, {}};
      AgentSpec b = a;
      b.tracker = choice;
      ad.trackers.push_back({name, assess_tracker(instances, choice, b, ask)});
    }
    if (i < lp.auto_tube.size() && lp.auto_tube[i].any()) {
      const AutoTube& at = lp.auto_tube[i];
      AgentSpec first = a;
      std::string eps_rule;
      first.tube.eps = first_auto_eps(first, pb.tau, &eps_rule);
      if (std::string cap; cap_auto_eps_for_formation(first, formation_tolerance(pb, static_cast<int>(i)), &cap))
        eps_rule += "; " + cap;
      if (!at.start_cap.empty()) eps_rule += "; " + at.start_cap;
      std::string v;
      for (Eigen::Index k = 0; k < a.tube.eps.size(); ++k) v += (k ? ", " : "") + number_text(a.tube.eps[k], 4);
      if (at.eps) ad.auto_note = "eps: auto, (" + v + ") to start (" + eps_rule + "); solve narrows it to the tube the controller keeps";
      if (!at.fields.empty()) ad.auto_note += (ad.auto_note.empty() ? "" : "; ") + at.field_rule;
    }
    // Warnings with their numbers.
    const std::string who = a.name + ": ";
    for (int k = 0; k < a.n(); ++k) {
      const double push = a.tube.w.size() > k ? a.tube.w[k] * pb.tau : 0.0;
      if (push > 0 && a.tube.eps[k] <= push)
        out.warnings.push_back(who + "eps " + number_text(a.tube.eps[k], 4) + " in " + coordinate(a, k) +
                               " is at most what the disturbance alone moves the state in one period (w tau = " +
                               number_text(a.tube.w[k], 4) + " x " + number_text(pb.tau, 4) + " = " +
                               number_text(push, 4) + "): no tracker can keep that tube; enlarge eps or shorten tau");
    }
    // The trackers' remarks on their own fields (abcd: a grid coarser than the tube).
    for (const auto& w : field_warnings(instances, a)) out.warnings.push_back(who + w);
    // The chosen tracker, then the fallbacks: each whose estimate is a minute or more.
    std::vector<std::string> order{ad.chosen};
    order.insert(order.end(), ad.fallbacks.begin(), ad.fallbacks.end());
    for (std::size_t o = 0; o < order.size(); ++o)
      for (const auto& t : ad.trackers)
        if (t.tracker == order[o] && t.assessment.ok && t.assessment.work_s >= kSlowTrackerSeconds)
          out.warnings.push_back(who + (o == 0 ? "its tracker " : "the fallback ") + t.tracker + " is estimated at " +
                                 seconds_or_minutes(t.assessment.work_s) + " of one core and " +
                                 format_bytes(t.assessment.memory_bytes) +
                                 (o == 0 ? "" : " (it runs when " + order[o - 1] + " finds no controller)") +
                                 "; coarser grids or another tracker would be faster");
    out.agents.push_back(std::move(ad));
  }
  // Two agents' tubes can change their distance by up to sqrt(2) (eps_i + eps_j) in position
  // (a box's diagonal each): a formation tolerance mu below that leaves no robust plan.
  for (const auto& f : pb.formation) {
    const double ei = planning::position_eps(pb.agents[f.i]), ej = planning::position_eps(pb.agents[f.j]);
    if (ei < 0 || ej < 0) continue;
    const double change = std::sqrt(2.0) * (ei + ej);
    if (!(change < f.mu))
      out.warnings.push_back("formation " + pb.agents[f.i].name + "-" + pb.agents[f.j].name + ": mu " +
                             number_text(f.mu, 4) +
                             " is not above sqrt(2) (eps_i + eps_j) = " + number_text(change, 4) +
                             " (2 eps sqrt(2) for equal tubes), what the two tubes alone can change the distance by: "
                             "no robust plan exists; position eps below " +
                             number_text(f.mu / (2 * std::sqrt(2.0)), 4) + " would do");
  }
  return out;
}

namespace {

// One agent's trackers, its auto note and their estimates, without its name.
std::string agent_block(const AgentAdvice& a) {
  std::ostringstream s;
  s.precision(kMessageDigits);
  s << a.chosen << (a.automatic ? " (auto's pick" : " (named in the file");
  if (a.automatic) {
    s << "; fallback order: " << a.chosen;
    for (const auto& f : a.fallbacks) s << ", then " << f;
  }
  s << ")\n";
  if (!a.auto_note.empty()) s << "    " << a.auto_note << "\n";
  for (const auto& t : a.trackers) {
    s << "    " << t.tracker << ": ";
    if (t.assessment.ok)
      s << "accepts, about " << seconds_or_minutes(t.assessment.work_s) << ", " << format_bytes(t.assessment.memory_bytes)
        << (t.assessment.summary.empty() ? "" : "; " + t.assessment.summary);
    else
      s << "refuses" << (t.assessment.field.empty() ? "" : " (" + t.assessment.field + ")") << ": " << t.assessment.message;
    s << "\n";
  }
  return s.str();
}

}  // namespace

std::string to_text(const Advice& adv) {
  std::ostringstream s;
  s.precision(kMessageDigits);
  s << "trackers per agent (estimates: one core's time, peak memory)\n";
  // Each agent's block without its name; consecutive agents with the same block share one.
  std::vector<std::string> names, blocks;
  for (const auto& a : adv.agents) {
    names.push_back(a.agent);
    blocks.push_back(agent_block(a));
  }
  for (const AgentRun& run : agent_runs(names, blocks)) s << "  " << run.label << ": " << blocks[run.first];
  // An agent's warning ("a7: eps 0.01 in y is at most ...") said by many alike agents in a row is
  // said once for all of them; a warning of no agent (a formation's) stands alone.
  std::vector<std::pair<std::string, std::vector<std::size_t>>> said;  // text, the agents saying it
  for (const auto& w : adv.warnings) {
    std::size_t agent = names.size();
    for (std::size_t i = 0; i < names.size(); ++i) {
      const std::string& n = names[i];
      if (w.size() > n.size() + 2 && w.compare(0, n.size(), n) == 0 && w.compare(n.size(), 2, ": ") == 0 &&
          (agent == names.size() || n.size() > names[agent].size()))
        agent = i;
    }
    if (agent == names.size()) {
      said.push_back({w, {}});
      continue;
    }
    const std::string text = w.substr(names[agent].size() + 2);
    auto it = std::find_if(said.begin(), said.end(), [&](const auto& e) { return !e.second.empty() && e.first == text; });
    if (it == said.end()) said.push_back({text, {agent}});
    else if (it->second.back() != agent) it->second.push_back(agent);
  }
  for (const auto& [text, agents] : said)
    s << "warning: " << (agents.empty() ? "" : agents_label(names, agents) + ": ") << text << "\n";
  return s.str();
}

}  // namespace marsyn
