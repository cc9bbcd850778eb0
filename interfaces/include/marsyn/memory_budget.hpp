#pragma once
// The memory budget every stage's estimate is judged against (docs/problem-format.md, "Checks"):
// one value per run, chosen by the front end (`marsyn --memory-budget`, the Python module's
// `memory_budget`) or, by default, half of the machine's physical memory. It travels in the
// request structs (LoadOptions, AssessRequest, TrackOptions), never through the environment, so
// that a tracker's assessment and its synthesis judge the same number. Header-only so that core
// and tracker plugins read one definition.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

namespace marsyn {

struct MemoryBudget {
  double bytes = 0;
  std::string source;  // where the value came from, for messages ("--memory-budget", ...)
};

// Half of the physical memory (8e9 bytes when the machine does not say).
inline MemoryBudget machine_memory_budget() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  const double phys = pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 8e9;
  return {phys / 2, "half of the physical memory; --memory-budget changes it"};
}

// "8e9", "512M", "2G", "1.5GB": bytes, or with a suffix K, M, G, T (powers of 1024) and an
// optional trailing B. Empty when the text is not a positive finite number of bytes.
inline std::optional<double> parse_bytes(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str()) return std::nullopt;
  std::string suffix = end;
  if (!suffix.empty() && (suffix.back() == 'B' || suffix.back() == 'b')) suffix.pop_back();
  double scale = 1;
  if (suffix == "K" || suffix == "k") scale = 1024.0;
  else if (suffix == "M" || suffix == "m") scale = 1024.0 * 1024;
  else if (suffix == "G" || suffix == "g") scale = 1024.0 * 1024 * 1024;
  else if (suffix == "T" || suffix == "t") scale = 1024.0 * 1024 * 1024 * 1024;
  else if (!suffix.empty()) return std::nullopt;
  v *= scale;
  if (!std::isfinite(v) || v <= 0) return std::nullopt;
  return v;
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
