#pragma once
// The default tracker: tube-local abstraction with sound growth-bound successor boxes and a
// time-indexed controller (paper Sec. 3.4).
#include <string>
#include <vector>

#include "marsyn/params.hpp"
#include "marsyn/tracker.hpp"
#include "synthesis.hpp"

namespace marsyn::abcd {

class AbcdTracker : public marsyn::Tracker {
 public:
  explicit AbcdTracker(const Params& p = {});
  static std::vector<ParamSpec> param_specs();

  std::string name() const override { return "abcd"; }
  TrackResult track(const TrackingProblem& problem, const TrackOptions& options) const override;
  TrackResult reach_avoid(const ReachAvoidProblem& problem, const TrackOptions& options) const override;
  std::shared_ptr<const Controller> read_controller(const std::string& path) const override;

  // Tests and benchmarks set these directly.
  SynthesisOptions options_for(const TrackOptions& o) const;

 private:
  SynthesisOptions base_;
  int threads_ = 0;  // 0: TrackOptions::threads decides
};

}  // namespace marsyn::abcd
