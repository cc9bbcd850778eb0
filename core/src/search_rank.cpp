#include "marsyn/core/search_rank.hpp"

#include <algorithm>
#include <limits>

namespace marsyn::search {

int best_candidate(const std::vector<Candidate>& candidates) {
  double fallback = std::numeric_limits<double>::infinity();
  for (const auto& c : candidates)
    if (c.lever.lever == Lever::FallBack) fallback = std::min(fallback, c.predicted_s);
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    // A knob that costs more than another tracker waits behind it: the knobs double their cost
    // each time (a funnel's substeps 16 -> 256: 17 s -> 128 s), another tracker is one tracking.
    if (candidates[k].lever.lever == Lever::TrackerLever && candidates[k].predicted_s > fallback) continue;
    return static_cast<int>(k);
  }
  return candidates.empty() ? -1 : 0;
}

Failure agent_failure(const Failure& f, std::size_t w) {
  Failure one;
  one.kind = f.kind;
  one.reason = f.reason;
  one.agents = {f.agents.at(w)};
  if (w < f.why.size()) one.why = {f.why[w]};
  if (w < f.nominal_saturation.size()) one.nominal_saturation = {f.nominal_saturation[w]};
  if (w < f.miss_share.size()) one.miss_share = {f.miss_share[w]};
  one.longest_horizon = f.longest_horizon;
  one.horizon_blocked = f.horizon_blocked;
  one.beyond_eps = f.beyond_eps;
  one.gap_eps_factor = f.gap_eps_factor;
  return one;
}

Proposal merge(const std::vector<Proposal>& picks, const Team& team) {
  Proposal m = unchanged(team);
  bool recheck = true;
  for (const Proposal& p : picks) {
    if (picks.size() == 1) m.lever = p.lever;
    for (int i : p.changed) {
      const auto at = static_cast<std::size_t>(i);
      if (at < p.agents.size()) m.agents[at] = p.agents[at];
      if (at < p.trackers.size() && at < m.trackers.size()) m.trackers[at] = p.trackers[at];
      if (at < p.input_share.size()) m.input_share[at] = p.input_share[at];
      if (std::find(m.changed.begin(), m.changed.end(), i) == m.changed.end()) m.changed.push_back(i);
    }
    m.changes.insert(m.changes.end(), p.changes.begin(), p.changes.end());
    if (p.replan) {
      m.replan = true;
      recheck = recheck && p.recheck;
    }
  }
  m.recheck = m.replan && recheck;
  return m;
}

std::string merged_action(const std::vector<std::string>& names, const std::vector<std::string>& agents) {
  if (names.empty()) return "";
  if (std::all_of(names.begin(), names.end(), [&](const std::string& n) { return n == names.front(); })) return names.front();
  std::string out;
  for (std::size_t k = 0; k < names.size(); ++k)
    out += (k ? "; " : "") + (k < agents.size() ? agents[k] + ": " : std::string()) + names[k];
  return out;
}

}  // namespace marsyn::search
