#include "marsyn/core/stage_memory.hpp"

#include <algorithm>
#include <atomic>
#include <fstream>
#include <sstream>
#include <string>

#include "marsyn/number_text.hpp"

namespace marsyn {

namespace {

// The largest high-water mark seen before a reset: the run's peak survives the stages' resets.
std::atomic<double> g_before_resets{0.0};

// A field of /proc/self/status in bytes ("VmHWM:  218332 kB"); 0 where it cannot be read.
double status_bytes(const std::string& key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key + ":", 0) == 0) {
      std::istringstream s(line.substr(key.size() + 1));
      double kb = 0;
      s >> kb;
      return kb * 1024.0;
    }
  return 0.0;
}

void fold(double bytes) {
  double seen = g_before_resets.load();
  while (bytes > seen && !g_before_resets.compare_exchange_weak(seen, bytes)) {
  }
}

// "5" resets the high-water mark to the current resident size (Linux 4.0 and later).
bool reset_high_water() {
  fold(status_bytes("VmHWM"));
  std::ofstream out("/proc/self/clear_refs");
  out << "5";
  out.flush();
  return static_cast<bool>(out);
}

// MB as the summary's total line counts them (2^20 bytes).
std::string mb(double bytes) { return number_text(bytes / 1048576.0, 3) + " MB"; }

}  // namespace

StageWatch::StageWatch(StagePeak& into) : into_(into) {
  resettable_ = reset_high_water();
  if (into_.peak_bytes == 0) into_.start_bytes = status_bytes("VmRSS");
}

StageWatch::~StageWatch() {
  const double peak = status_bytes("VmHWM");
  fold(peak);
  into_.peak_bytes = std::max(into_.peak_bytes, peak);
}

double run_peak_memory_bytes() {
  const double now = status_bytes("VmHWM");
  fold(now);
  return g_before_resets.load();
}

std::string stage_memory_text(const StageMemory& m) {
  std::string s;
  auto add = [&](const char* name, const StagePeak& p, double predicted) {
    if (p.peak_bytes <= 0) return;
    s += (s.empty() ? "" : ", ") + std::string(name) + " " + mb(p.added_bytes());
    if (predicted > 0) s += " (" + mb(predicted) + " predicted)";
  };
  add("plan", m.plan, m.plan_predicted_bytes);
  add("tracking", m.track, 0);
  add("certification", m.certify, 0);
  add("verification", m.verify, m.verify_predicted_bytes);
  if (!m.per_stage && !s.empty()) s += " (the run's peak so far at each stage: the system keeps one high-water mark)";
  return s;
}

}  // namespace marsyn
