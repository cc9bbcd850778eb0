#pragma once
// Phi_track synthesis over the tube (one backward sweep) and the whole-domain reach-avoid
// fixed point, both on the same sound successor boxes.
#include <functional>

#include "controller_file.hpp"
#include "marsyn/collective.hpp"
#include "marsyn/tracker.hpp"
#include "successor_box.hpp"

namespace marsyn::abcd {

// The tracker's parameters are members of these options (and of `successor`), each declared
// once in abcd_tracker.cpp (marsyn/param_set.hpp): the default is the member's initializer here,
// and the listing, the parsing and the range checks read that one declaration.
struct Options {
  // Worker threads (the parameter `threads`; 0: AbcdTracker::options_for takes the run's
  // TrackOptions::threads, else the machine's). The sweep runs at least one.
  int threads = 0;
  SuccessorOptions successor;
  // Skip an input from a column when the RK4 image of the column's centre (w = 0) lands outside
  // the next tube, before computing its box: the exact centre image lies in every sound
  // successor box, so such a box cannot be inside; the margin absorbs the RK4 error. It only
  // avoids work and can never admit an input.
  bool prefilter = true;
  int prefilter_substeps = 2;
  const SuccessorHook* hook = nullptr;
  double memory_budget_bytes = 8e9;
  // Parts of each sampling period with their own enclosure box (continuous-time guarantee).
  int enclosure_substeps = 8;
  int enclosure_block = 4;  // cells per block along non-invariant coordinates (period_enclosure.hpp)
  // Ranks sharing the sweep (split_sweep.hpp); nullptr: this process alone.
  const Collective* collective = nullptr;
  std::function<void(int done, int total)> progress;  // after each backward step; may be empty
  // The run's stop request (TrackOptions::stop), polled every kStopEvery columns of the sweep by
  // each thread; not polled when ranks share the sweep (they must leave it together). May be empty.
  std::function<bool()> stop;
};

TrackResult synthesize_track(const TrackingProblem& p, const Options& o);
TrackResult synthesize_reach_avoid(const ReachAvoidProblem& p, const Options& o);

long long peak_rss_bytes();

}  // namespace marsyn::abcd
