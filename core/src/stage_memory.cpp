#include "marsyn/core/stage_memory.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>

#include "marsyn/number_text.hpp"

namespace marsyn {

namespace {

// The kernel's high-water mark (VmHWM) in bytes; 0 where it cannot be read.
double high_water_bytes() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmHWM:", 0) == 0) {
      std::istringstream s(line.substr(6));
      double kb = 0;
      s >> kb;
      return kb * 1024.0;
    }
  return 0.0;
}

// The resident size now, from /proc/self/statm (pages); 0 where it cannot be read.
double resident_bytes() {
  std::ifstream in("/proc/self/statm");
  double size = 0, resident = 0;
  if (!(in >> size >> resident)) return 0.0;
  return resident * static_cast<double>(sysconf(_SC_PAGESIZE));
}

// MB as the summary's total line counts them (2^20 bytes).
std::string mb(double bytes) { return number_text(bytes / 1048576.0, 3) + " MB"; }

}  // namespace

// The sampler: the resident size every few milliseconds while the stage runs.
struct StageWatch::Sampler {
  std::mutex m;
  std::condition_variable cv;
  bool done = false;
  double largest = 0;
  std::thread thread;
};

StageWatch::StageWatch(StagePeak& into) : into_(into), high_water_at_start_(high_water_bytes()), sampler_(new Sampler) {
  const double now = resident_bytes();
  if (into_.peak_bytes == 0) into_.start_bytes = now;
  sampler_->largest = now;
  Sampler* s = sampler_.get();
  s->thread = std::thread([s] {
    std::unique_lock<std::mutex> lock(s->m);
    while (!s->cv.wait_for(lock, std::chrono::milliseconds(5), [s] { return s->done; }))
      s->largest = std::max(s->largest, resident_bytes());
  });
}

StageWatch::~StageWatch() {
  {
    std::lock_guard<std::mutex> lock(sampler_->m);
    sampler_->done = true;
  }
  sampler_->cv.notify_all();
  sampler_->thread.join();
  double peak = std::max(sampler_->largest, resident_bytes());
  // A stage that set the process's record has it exactly (a spike between two samples too).
  const double high_water = high_water_bytes();
  if (high_water > high_water_at_start_) peak = std::max(peak, high_water);
  into_.peak_bytes = std::max(into_.peak_bytes, peak);
}

std::string stage_memory_text(const StageMemory& m) {
  std::string s;
  auto add = [&](const char* name, const StagePeak& p, double predicted, const char* kind) {
    if (p.peak_bytes <= 0) return;
    s += (s.empty() ? "" : ", ") + std::string(name) + " " + mb(p.added_bytes());
    if (predicted > 0) s += " (" + mb(predicted) + " predicted" + kind + ")";
  };
  add("plan", m.plan, m.plan_predicted_bytes, "");
  // The trackers' figures are upper ones (abcd's successor cache is counted full).
  add("tracking", m.track, m.track_predicted_bytes, " at most");
  add("certification", m.certify, 0, "");
  add("verification", m.verify, m.verify_predicted_bytes, "");
  return s;
}

}  // namespace marsyn
