#include "marsyn/core/search_report.hpp"

#include <cstdio>
#include <utility>

namespace marsyn {

std::vector<SearchChange> grouped(const std::vector<SearchChange>& changes, std::size_t team_size) {
  std::vector<SearchChange> out;
  std::vector<std::vector<std::string>> who;  // per entry of out: the agents it stands for
  for (const auto& c : changes) {
    std::size_t at = 0;
    while (at < out.size() && (c.agent.empty() || who[at].empty() || out[at].what != c.what || out[at].from != c.from ||
                               out[at].to != c.to))
      ++at;
    if (at == out.size()) {
      out.push_back(c);
      who.push_back(c.agent.empty() ? std::vector<std::string>{} : std::vector<std::string>{c.agent});
    } else {
      who[at].push_back(c.agent);
    }
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    const auto& w = who[i];
    if (w.size() < 2) continue;
    if (team_size >= 2 && w.size() == team_size) {
      out[i].agent = "every agent";
      continue;
    }
    std::string names;
    const std::size_t shown = w.size() > 4 ? 3 : w.size();
    for (std::size_t k = 0; k < shown; ++k)
      names += (k == 0 ? "" : k + 1 == shown && shown == w.size() ? " and " : ", ") + w[k];
    if (shown < w.size()) names += " and " + std::to_string(w.size() - shown) + " more";
    out[i].agent = names;
  }
  return out;
}

std::string SearchReport::tried() const {
  std::vector<std::pair<std::string, int>> counts;  // in the order first run
  for (std::size_t r = 1; r < rounds.size(); ++r) {
    // A round of per-agent levers ("a1: <lever>; a2: <lever>", search_rank.hpp) counts once
    // for each lever it ran.
    std::vector<std::string> levers;
    const std::string& action = rounds[r].action;
    // The levers of a round are joined by "; " outside brackets (a lever's own words may hold one).
    auto next_separator = [&](std::size_t from) {
      int depth = 0;
      for (std::size_t i = from; i + 1 < action.size(); ++i) {
        if (action[i] == '(') ++depth;
        else if (action[i] == ')') --depth;
        else if (depth <= 0 && action[i] == ';' && action[i + 1] == ' ') return i;
      }
      return std::string::npos;
    };
    for (std::size_t from = 0; from <= action.size();) {
      std::size_t to = next_separator(from);
      if (to == std::string::npos) to = action.size();
      std::string part = action.substr(from, to - from);
      if (const auto colon = part.find(": "); colon != std::string::npos && next_separator(0) != std::string::npos)
        part = part.substr(colon + 2);
      bool seen = false;
      for (const auto& l : levers) seen = seen || l == part;
      if (!seen) levers.push_back(part);
      from = to + 2;
    }
    for (const auto& lever : levers) {
      auto it = counts.begin();
      while (it != counts.end() && it->first != lever) ++it;
      if (it == counts.end()) counts.emplace_back(lever, 1);
      else ++it->second;
    }
  }
  if (counts.empty()) return "tried: no lever (one round)";
  std::string s = "tried: ";
  for (std::size_t i = 0; i < counts.size(); ++i)
    s += (i ? ", " : "") + counts[i].first + " x" + std::to_string(counts[i].second);
  return s;
}

std::string SearchReport::message() const {
  char head[64];
  std::snprintf(head, sizeof head, " after %zu round%s and %.3g s; ", rounds.size(), rounds.size() == 1 ? "" : "s", time_s);
  std::string s = "stopped: " + stop_reason + head + tried();
  if (!not_tried.empty()) {
    s += "; not tried:";
    for (std::size_t i = 0; i < not_tried.size(); ++i)
      s += std::string(i ? "," : "") + " " + not_tried[i].lever + " (" + not_tried[i].why + ")";
  }
  return s;
}

}  // namespace marsyn
