#pragma once
// The memory budget every stage's estimate is judged against (docs/problem-format.md, "Checks"):
// MARSYN_MEMORY_BUDGET (bytes; suffixes K, M, G, T accepted, powers of 1024, an optional trailing
// B) or, by default, half of the machine's physical memory. Core checks the planner's estimate
// against it; a tracker's assess() checks its own (the process-wide value: `marsyn
// --memory-budget` sets the variable before any problem is loaded). Header-only so that core and
// tracker plugins read one definition.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace marsyn {

// The budget in bytes, and in `source` a short description for messages. NaN when the variable
// is set but malformed (core's loader reports that as a located error before any tracker runs).
inline double memory_budget_from_environment(std::string* source = nullptr) {
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
    if (end == env || !std::isfinite(v) || v <= 0) return NAN;
    if (source) *source = "MARSYN_MEMORY_BUDGET";
    return v;
  }
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  const double phys = pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 8e9;
  if (source) *source = "half of the physical memory; set MARSYN_MEMORY_BUDGET or --memory-budget to change it";
  return phys / 2;
}

// "1.5 GiB", "12.0 MiB", "4096 bytes", "3.84e+20 bytes": the form every budget message uses.
inline std::string format_bytes(double bytes) {
  char buf[64];
  if (bytes >= 1e15) std::snprintf(buf, sizeof buf, "%.3g bytes", bytes);
  else if (bytes >= 1 << 30) std::snprintf(buf, sizeof buf, "%.1f GiB", bytes / (1 << 30));
  else if (bytes >= 1 << 20) std::snprintf(buf, sizeof buf, "%.1f MiB", bytes / (1 << 20));
  else std::snprintf(buf, sizeof buf, "%.0f bytes", bytes);
  return buf;
}

}  // namespace marsyn
