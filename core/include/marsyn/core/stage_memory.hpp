#pragma once
// Resident memory stage by stage (issue 50, "memory budget per stage"): how much each stage of a
// solve added to the process at its peak, next to what `check` predicted for it, so that a user
// of a large team sees which stage sets the machine they need. Read from the kernel's high-water
// mark (VmHWM), reset at each stage's start (/proc/self/clear_refs), so one stage's peak is not
// hidden behind an earlier one's.
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
  double verify_predicted_bytes = 0;  // verification_memory_bytes (`check`'s)
  bool per_stage = true;            // false where the high-water mark cannot be reset: each peak is then the run's so far
};

// One stage's measurement: the high-water mark reset when it starts, read when it ends.
class StageWatch {
 public:
  explicit StageWatch(StagePeak& into);
  ~StageWatch();
  StageWatch(const StageWatch&) = delete;
  StageWatch& operator=(const StageWatch&) = delete;
  bool resettable() const { return resettable_; }

 private:
  StagePeak& into_;
  bool resettable_ = false;
};

// The process's resident peak over the whole run (the stages' resets folded in); 0 where unknown.
double run_peak_memory_bytes();

// "plan 401 MB (412 MB predicted), tracking 66 MB, certification 12 MB, verification 180 MB":
// what each stage added at its peak.
std::string stage_memory_text(const StageMemory& m);

}  // namespace marsyn
