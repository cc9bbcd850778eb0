#include "marsyn/core/problem/input_limits.hpp"

#include <cmath>
#include <cstdlib>

#include "marsyn/core/problem/config_error.hpp"
#include "marsyn/number_text.hpp"

namespace marsyn {

std::string name_defect(const std::string& name) {
  if (name.empty()) return "expected a non-empty name";
  if (name.size() > kMaxNameLength)
    return "a name may have at most " + std::to_string(kMaxNameLength) + " characters, got " +
           std::to_string(name.size()) + " ('" + name.substr(0, 20) + "...')";
  if (name[0] == '.') return "a name may not start with '.', got '" + name + "'";
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                    c == '-' || c == '.';
    if (!ok)
      return "a name may contain only letters, digits, '_', '-' and '.' (it becomes a file name), got '" + name + "'";
  }
  return {};
}

std::string name_from_stem(const std::string& stem) {
  std::string out;
  for (const char c : stem) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                    c == '-' || c == '.';
    out += ok ? c : '_';
  }
  while (!out.empty() && out[0] == '.') out.erase(0, 1);
  if (out.size() > kMaxNameLength) out.resize(kMaxNameLength);
  return out.empty() ? "problem" : out;
}

MemoryEstimate planner_memory(const Problem& pb) {
  const double steps = static_cast<double>(pb.horizon) + 1;
  const double N = static_cast<double>(pb.agents.size());
  double blocks = 0, nmax = 0;
  for (const auto& a : pb.agents) {
    const double k = a.n() + a.m();
    blocks += 32.0 * k * k;  // dynamics Jacobians, gains, value-function blocks: 4 doubles per entry
    nmax = std::max(nmax, static_cast<double>(a.n()));
  }
  const double pairs = (pb.pairwise_collision ? N * (N - 1) / 2 : 0.0) + static_cast<double>(pb.formation.size());
  const double obstacle_rows = N * static_cast<double>(pb.obstacles.size());
  const double per_step = blocks + pairs * 32.0 * (2 * nmax + 1) + obstacle_rows * 32.0 * (nmax + 1);
  MemoryEstimate e;
  e.bytes = steps * per_step;
  e.detail = number_text(steps, 3) + " steps x (" + number_text(N, 3) + " agents' blocks + " + number_text(pairs, 3) +
             " pair and " + number_text(obstacle_rows, 3) + " obstacle constraint rows)";
  return e;
}

}  // namespace marsyn
