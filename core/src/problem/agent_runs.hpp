#pragma once
// Teams of hundreds print one line per kind of agent, not per agent: three or more consecutive
// agents whose lines say the same thing (all but the name) share one, labelled "a1 .. a400 (400
// agents)"; a small team keeps a line per agent.
#include <cstddef>
#include <string>
#include <vector>

namespace marsyn {

struct AgentRun {
  std::size_t first = 0, count = 0;  // agents first .. first + count - 1
  std::string label;                 // "a1" or "a1 .. a9 (9 agents)"
};

// keys[i]: agent i's line without its name; names[i]: its name.
inline std::vector<AgentRun> agent_runs(const std::vector<std::string>& names, const std::vector<std::string>& keys) {
  std::vector<AgentRun> out;
  for (std::size_t i = 0; i < names.size();) {
    std::size_t j = i + 1;
    while (j < names.size() && keys[j] == keys[i]) ++j;
    if (j - i < 3) j = i + 1;
    const std::size_t n = j - i;
    AgentRun r{i, n, names[i]};
    if (n > 1) r.label += " .. " + names[j - 1] + " (" + std::to_string(n) + " agents)";
    out.push_back(std::move(r));
    i = j;
  }
  return out;
}

// The agents `indices` (ascending) by name, runs of three or more in a row as "a1 .. a9 (9 agents)":
// "u1 .. u4 (4 agents), u6".
inline std::string agents_label(const std::vector<std::string>& names, const std::vector<std::size_t>& indices) {
  std::string out;
  for (std::size_t k = 0; k < indices.size();) {
    std::size_t e = k + 1;
    while (e < indices.size() && indices[e] == indices[e - 1] + 1) ++e;
    if (e - k < 3) e = k + 1;
    out += (out.empty() ? "" : ", ") + names[indices[k]];
    if (e - k > 1) out += " .. " + names[indices[e - 1]] + " (" + std::to_string(e - k) + " agents)";
    k = e;
  }
  return out;
}

}  // namespace marsyn
