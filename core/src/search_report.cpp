#include "marsyn/core/search_report.hpp"

#include <cstdio>
#include <utility>

namespace marsyn {

std::string SearchReport::tried() const {
  std::vector<std::pair<std::string, int>> counts;  // in the order first run
  for (std::size_t r = 1; r < rounds.size(); ++r) {
    auto it = counts.begin();
    while (it != counts.end() && it->first != rounds[r].action) ++it;
    if (it == counts.end()) counts.emplace_back(rounds[r].action, 1);
    else ++it->second;
  }
  if (counts.empty()) return "tried: the first attempt only";
  std::string s = "tried: ";
  for (std::size_t i = 0; i < counts.size(); ++i)
    s += (i ? ", " : "") + counts[i].first + " x" + std::to_string(counts[i].second);
  return s;
}

std::string SearchReport::message() const {
  char head[64];
  std::snprintf(head, sizeof head, " after %zu round%s and %.2f s; ", rounds.size(), rounds.size() == 1 ? "" : "s", time_s);
  std::string s = "stopped: " + stop_reason + head + tried();
  if (!not_tried.empty()) {
    s += "; not tried:";
    for (std::size_t i = 0; i < not_tried.size(); ++i)
      s += std::string(i ? "," : "") + " " + not_tried[i].lever + " (" + not_tried[i].why + ")";
  }
  return s;
}

}  // namespace marsyn
