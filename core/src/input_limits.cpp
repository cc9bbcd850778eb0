#include "marsyn/core/input_limits.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "marsyn/core/config_error.hpp"

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

std::string format_bytes(double bytes) {
  char buf[64];
  if (bytes >= 1e15) std::snprintf(buf, sizeof buf, "%.3g bytes", bytes);
  else if (bytes >= 1 << 30) std::snprintf(buf, sizeof buf, "%.1f GiB", bytes / (1 << 30));
  else if (bytes >= 1 << 20) std::snprintf(buf, sizeof buf, "%.1f MiB", bytes / (1 << 20));
  else std::snprintf(buf, sizeof buf, "%.0f bytes", bytes);
  return buf;
}

double memory_budget_bytes(std::string* source) {
  if (const char* env = std::getenv("MARSYN_MEMORY_BUDGET"); env && *env) {
    char* end = nullptr;
    double v = std::strtod(env, &end);
    std::string suffix = end ? end : "";
    if (!suffix.empty() && (suffix.back() == 'B' || suffix.back() == 'b')) suffix.pop_back();
    double scale = 1;
    if (suffix == "K" || suffix == "k") scale = 1024.0;
    else if (suffix == "M" || suffix == "m") scale = 1024.0 * 1024;
    else if (suffix == "G" || suffix == "g") scale = 1024.0 * 1024 * 1024;
    else if (suffix == "T" || suffix == "t") scale = 1024.0 * 1024 * 1024 * 1024;
    else if (!suffix.empty()) v = NAN;
    v *= scale;
    if (end == env || !std::isfinite(v) || v <= 0)
      throw ConfigError("environment", 0, 0, "MARSYN_MEMORY_BUDGET",
                        std::string("expected a positive number of bytes such as 8e9 or 8G, got '") + env + "'");
    if (source) *source = "MARSYN_MEMORY_BUDGET";
    return v;
  }
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  const double phys = pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 8e9;
  if (source) *source = "half of the physical memory; set MARSYN_MEMORY_BUDGET or --memory-budget to change it";
  return phys / 2;
}

namespace {
std::string g(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}
}  // namespace

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
  e.detail = g(steps) + " steps x (" + g(N) + " agents' blocks + " + g(pairs) + " pair and " + g(obstacle_rows) +
             " obstacle constraint rows)";
  return e;
}

MemoryEstimate tracker_state_memory(const AgentSpec& a, int horizon) {
  double cells = 1;
  for (int i = 0; i < a.n(); ++i) cells *= std::floor(2 * a.eps[i] / a.eta_x[i]) + 1;
  MemoryEstimate e;
  e.bytes = (static_cast<double>(horizon) + 1) * cells * 2 + 2 * cells * 8;
  e.detail = g(cells) + " tube cells per step x " + std::to_string(horizon + 1) + " steps";
  return e;
}

MemoryEstimate tracker_input_memory(const AgentSpec& a) {
  double inputs = 1;
  for (int j = 0; j < a.m(); ++j)
    inputs *= std::floor((a.input_bounds.hi[j] - a.input_bounds.lo[j]) / a.eta_u[j] + 1e-9) + 1;
  MemoryEstimate e;
  e.bytes = inputs * (a.m() + 1) * 8.0;
  e.detail = g(inputs) + " grid inputs over U";
  return e;
}

}  // namespace marsyn
