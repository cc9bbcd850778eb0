#pragma once
// Resident memory stage by stage (issue 50, "memory budget per stage"): how much each stage of a
// solve added to the process at its peak, next to what `check` predicted for it, so that a user
// of a large team sees which stage sets the machine they need. The resident size is sampled every
// 5 ms while a stage runs, and a stage that raises the kernel's high-water mark (VmHWM) has that
// exactly. The mark itself is never reset: /usr/bin/time and the like report the run's true peak.
#include <memory>
#include <string>

namespace marsyn {

struct StagePeak {
  double start_bytes = 0;  // resident at the stage's first start
  double peak_bytes = 0;   // the largest resident size while it ran (over all its rounds); 0: not run
  // What the stage added at its peak over what was resident when it started.
  double added_bytes() const { return peak_bytes > start_bytes ? peak_bytes - start_bytes : 0.0; }
};

struct StageMemory {
  StagePeak plan, track, certify, verify;
  double plan_predicted_bytes = 0;    // the planner's own figure at the horizon planned (`check`'s)
  double track_predicted_bytes = 0;   // tracking_memory (`check`'s, at the horizon tracked)
  double verify_predicted_bytes = 0;  // verification_memory_bytes (`check`'s)
};

// One stage's measurement, from construction to destruction (folded into `into` over rounds).
class StageWatch {
 public:
  explicit StageWatch(StagePeak& into);
  ~StageWatch();
  StageWatch(const StageWatch&) = delete;
  StageWatch& operator=(const StageWatch&) = delete;

 private:
  struct Sampler;
  StagePeak& into_;
  double high_water_at_start_;
  std::unique_ptr<Sampler> sampler_;
};

// "plan 401 MB (412 MB predicted), tracking 66 MB (80 MB predicted at most), certification 12 MB,
// verification 180 MB (190 MB predicted)":
// what each stage added at its peak.
std::string stage_memory_text(const StageMemory& m);

}  // namespace marsyn
