#pragma once
// The funnel tracker: time-varying LQR feedback around the nominal, held over each period, with
// a sound zonotope verification of the closed loop (docs/tracker.md "funnel", docs/soundness.md
// section 11). Its cost grows polynomially with the state dimension, not exponentially.
#include <functional>
#include <string>
#include <vector>

#include "funnel_synthesis.hpp"
#include "marsyn/params.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn::funnel {

// The tracker's parameters with their defaults, each declared once in funnel_tracker.cpp
// (marsyn/param_set.hpp): the listing, the parsing and the checks read that declaration. The
// integers are long, as written in the config, so that a range is checked before narrowing.
struct Options {
  long substeps = 16;
  long parts = 8;  // the parameter enclosure_substeps
  long picard_iterations = 20;
  long max_generators = 0;
  std::vector<double> initial_radius;  // empty: initial_fraction * eps
  double initial_fraction = 0.1;
  double state_weight = 1.0, input_weight = 1.0, terminal_weight = 1.0;
  bool weight_search = true;
  long rk4_substeps = 4;
  std::string enclosure = "second_order";  // or "mean_value" (the first-order form, for comparison)
  long tightness_runs = 32;  // sampled runs of the tightness figure; 0: none
  long reach_order = 24;
  std::string verified_set = "parallelotope";  // or "zonotope"
  long set_order = 8;
  bool shift_inputs = true;  // VerifyOptions::shift_inputs
  bool invariant_sets = true;  // make_invariant after the verification (funnel_synthesis.hpp)
  long box_substeps = 0;
  long split_depth = 3;  // VerifyOptions::split_depth
  long input_rounds = 5;  // input-aware redesigns (input_weights.hpp) after a miss with saturated inputs
};

class FunnelTracker : public marsyn::Tracker {
 public:
  explicit FunnelTracker(const Params& p = {});
  static std::vector<ParamSpec> param_specs();

  std::string name() const override { return "funnel"; }
  TrackerCapabilities capabilities() const override {
    return {.initial_set = true, .state_dependent_disturbance = true};
  }
  TrackResult track(const TrackingProblem& problem, const TrackOptions& options) const override;
  TrackerAssessment assess(const AgentSpec& agent, int horizon, double tau) const override;
  bool refine(AgentSpec& agent) const override;
  // The outer search's knobs (docs/search.md), for a tube miss: "more enclosure generators"
  // (reach_order x 2, up to 64) and "more enclosure substeps" (substeps x 2, up to 256): the
  // verification's own error; "stiffer feedback" (state_weight x 4, up to 1e4). No lever for
  // split_depth: on tests/problems/15 "deeper splits" (5, 7, 8) took 18 s of rounds and got the
  // boat no controller (docs/funnel.md, "Splitting").
  std::vector<TrackerLever> levers(const AgentSpec& agent) const override;
  bool apply_lever(const std::string& name, const TrackFailure& failure, AgentSpec& agent) const override;
  std::shared_ptr<const Controller> read_controller(const std::string& path) const override;

  const Options& options() const { return s_; }
  // Test hook: scales the second-order remainder (docs/soundness.md section 11); 1 is sound.
  void scale_remainder_for_tests(double scale) { remainder_scale_ = scale; }
  // Test hook: the verified run's reachable-set enclosures (VerifyOutcome::reach) go to *out.
  void keep_reach_sets_for_tests(std::vector<std::vector<Zonotope>>* out) { reach_out_ = out; }

 private:
  // The verification's options from the settings (initial box from eps where not configured).
  // The initial box's half-widths: the knob initial_radius when given (it must hold a stated
  // initial set), else the stated set (TrackingProblem::initial_radius), else initial_fraction eps.
  Eigen::VectorXd initial_box(const Eigen::VectorXd& eps, const Eigen::VectorXd& stated) const;
  // The first coordinate in which the knob initial_radius, when given, is narrower than the
  // stated initial set (which it may only widen), or -1.
  int uncovered_coordinate(const Eigen::VectorXd& stated) const;
  VerifyOptions verify_options(const Eigen::VectorXd& eps, const Eigen::VectorXd& stated) const;
  struct Search {
    VerifyOutcome best;
    int order = 0, weight_choices = 0, attempts = 0;  // the kept pass's reach order; LQR runs; verifications
    double gain_time = 0, verify_time = 0;
    bool split_tried = false;  // the furthest gains verified again with splits
    int input_rounds = 0;      // input-aware redesigns verified
    int reweighted_rows = 0;   // (step, input) rows whose R the last of them raised
    int input_reached = -1;    // the furthest step they verified (when none verified)
    bool input_aware = false;  // the verified funnel is one of them
    bool stopped = false;      // the run's stop request ended the search
  };
  class Ladder;  // search's run (funnel_tracker.cpp)
  Search search(const TrackingProblem& p, const std::function<bool()>& stop) const;

  Options s_;
  double remainder_scale_ = 1.0;
  std::vector<std::vector<Zonotope>>* reach_out_ = nullptr;
};

}  // namespace marsyn::funnel
