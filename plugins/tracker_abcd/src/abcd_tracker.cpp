#include "abcd_tracker.hpp"

#include <thread>

#include "controller_file.hpp"

namespace marsyn::abcd {

AbcdTracker::AbcdTracker(const Params& p) {
  base_.successor.substeps = static_cast<int>(p.integer("substeps", 2));
  base_.successor.taylor_terms = static_cast<int>(p.integer("taylor_terms", 10));
  base_.successor.picard_iterations = static_cast<int>(p.integer("picard_iterations", 12));
  base_.prefilter = p.boolean("prefilter", true);
  base_.prefilter_substeps = static_cast<int>(p.integer("prefilter_substeps", 2));
  threads_ = static_cast<int>(p.integer("threads", 0));
  base_.enclosure_substeps = static_cast<int>(p.integer("enclosure_substeps", 8));
  if (base_.enclosure_substeps < 1 || base_.enclosure_substeps > SuccessorBox::kMaxEncloseSubsteps)
    throw ParamError("enclosure_substeps", "expected an integer in [1, 64]");
  base_.enclosure_block = static_cast<int>(p.integer("enclosure_block", 4));
  if (base_.enclosure_block < 1 || base_.enclosure_block > 64) throw ParamError("enclosure_block", "expected an integer in [1, 64]");
  if (base_.successor.substeps < 1 || base_.successor.substeps > 1000)
    throw ParamError("substeps", "expected an integer in [1, 1000]");
  if (base_.successor.taylor_terms < 4 || base_.successor.taylor_terms > 16)
    throw ParamError("taylor_terms", "expected an integer in [4, 16]");
  if (base_.successor.picard_iterations < 1 || base_.successor.picard_iterations > 100)
    throw ParamError("picard_iterations", "expected an integer in [1, 100]");
  if (base_.prefilter_substeps < 1 || base_.prefilter_substeps > 1000)
    throw ParamError("prefilter_substeps", "expected an integer in [1, 1000]");
  if (threads_ < 0 || threads_ > 256) throw ParamError("threads", "expected an integer in [0, 256]");
}

std::vector<ParamSpec> AbcdTracker::param_specs() {
  return {
      {"substeps", ParamType::Int, "2", "[1, 1000]",
       "substeps of the sound enclosure over one sampling period (more: tighter boxes, slower)"},
      {"taylor_terms", ParamType::Int, "10", "[4, 16]", "matrix-exponential series terms before the rigorous tail bound"},
      {"picard_iterations", ParamType::Int, "12", "[1, 100]", "a priori enclosure attempts before an input is dropped"},
      {"prefilter", ParamType::Bool, "true", "true|false",
       "skip inputs whose RK4 centre image leaves the next tube before computing their box (work only)"},
      {"prefilter_substeps", ParamType::Int, "2", "[1, 1000]", "RK4 substeps of the prefilter's centre image"},
      {"threads", ParamType::Int, "0", "[0, 256]", "worker threads; 0: the run's thread option"},
      {"enclosure_substeps", ParamType::Int, "8", "[1, 64]",
       "boxes per sampling period enclosing the closed loop between samples (continuous-time guarantee; more: tighter)"},
      {"enclosure_block", ParamType::Int, "4", "[1, 64]",
       "cells per block enclosed together between samples, along coordinates the field reads (fewer: tighter, slower)"},
  };
}

SynthesisOptions AbcdTracker::options_for(const TrackOptions& o) const {
  SynthesisOptions s = base_;
  int t = threads_ > 0 ? threads_ : o.threads;
  if (t <= 0) t = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  s.threads = t;
  s.memory_budget_bytes = o.memory_budget_bytes;
  return s;
}

TrackResult AbcdTracker::track(const TrackingProblem& problem, const TrackOptions& options) const {
  SynthesisOptions s = options_for(options);
  s.successor.tau = problem.tau;
  if (!s.hook) s.hook = dynamic_cast<const SuccessorBoundHook*>(problem.dynamics.get());
  return synthesize_track(problem, s);
}

TrackResult AbcdTracker::reach_avoid(const ReachAvoidProblem& problem, const TrackOptions& options) const {
  SynthesisOptions s = options_for(options);
  s.successor.tau = problem.tau;
  if (!s.hook) s.hook = dynamic_cast<const SuccessorBoundHook*>(problem.dynamics.get());
  return synthesize_reach_avoid(problem, s);
}

std::shared_ptr<const Controller> AbcdTracker::read_controller(const std::string& path) const {
  return abcd::read_controller(path);
}

}  // namespace marsyn::abcd
