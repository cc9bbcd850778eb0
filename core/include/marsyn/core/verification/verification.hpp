#pragma once
// Multi-agent verification (evidence beside the proof): every agent runs its own controller on
// its local state and time only, under many disturbance scenarios, and the real global
// specification is checked on the simulated states. The nominal inputs are also run open loop
// under the paper's constant disturbances, to show what fails without feedback.
#include <functional>

#include "marsyn/collective.hpp"
#include <string>
#include <vector>

#include "marsyn/core/verification/closed_loop.hpp"
#include "marsyn/core/verification/spec_monitor.hpp"

namespace marsyn {

// The closed-loop runs when none are asked for: 1000 for teams of up to 100 agents, else
// 100,000 agent runs spread over the team (250 for 400 agents), at least 200. The runs are
// evidence that can refute, not the guarantee (docs/soundness.md): a run of 400 robots is 400
// closed loops and every pair among them, and its cost grows faster than the team.
int default_verification_runs(int agents);

struct VerificationOptions {
  int runs = 0;  // closed-loop runs in total (at least the 4 paper scenarios + 1 undisturbed); 0: default_verification_runs
  std::uint64_t seed = 1;
  int threads = 2;
  int fine_substeps = 20;  // RK4 steps per period; the dense check's resolution is tau / fine_substeps
  std::function<void(int done, int total)> progress;  // may be empty
  // The ranks of an MPI run: run r on rank r mod size, summaries exchanged (mpi_runs.hpp), the
  // same report on every rank. nullptr: this process alone.
  const Collective* collective = nullptr;
  bool all_pairs = false;  // SimulationSetup::all_pairs: the reference check (tests, benchmark)
};

// What the verification adds to the process at its peak: the ten runs kept for the report (the
// nominal, four open-loop and four closed-loop runs under the paper's disturbances, the worst
// run) hold the product state and the margins at every substep of the horizon. The runs
// themselves keep only their minima. Measured on the unicycle field (scripts/unicycle_field.py):
// 19 / 74 / 280 MB at 25 / 100 / 400 robots against 23 / 80 / 317 MB from this.
double verification_memory_bytes(const Problem& problem, int fine_substeps = VerificationOptions{}.fine_substeps);

struct RunSummary {
  Scenario scenario;
  bool satisfied = true;
  double min_margin = 0;
  std::string worst;
  bool left_tube = false;
  bool outside_domain = false;
  StepMargins between;  // dense, strictly between the samples
  double sampled_margin = 0;
};

// A run kept for plots and animations.
struct KeptRun {
  std::string label;  // e.g. "feedback, paper disturbance (+W, -W, ...)"
  std::vector<Eigen::VectorXd> states;
  SpecEvaluation spec;
  // Dense in time: the margins at every integration substep (samples included) and their times.
  std::vector<double> dense_t;
  std::vector<StepMargins> dense;
};

// One open-loop run: its smallest margin per part of the specification (1e300 when the problem
// has no such part), so that a collision is visible even when a missed goal is worse.
struct OpenLoopRun {
  std::string label;  // the paper scenario, e.g. "(+W, -W, +W, ... (alternating))"
  bool satisfied = true;
  struct Part {
    double margin = 1e300;
    int step = -1;
  } obstacle, collision, formation;
  double goal = 1e300;  // at the final step
};

struct VerificationReport {
  int runs = 0;
  int violations = 0;          // runs violating the global specification
  int tube_violations = 0;     // runs where some agent left its tube (must be 0 for sound controllers)
  int outside_domain = 0;      // runs where some controller had no input for its state
  double min_margin = 1e300;   // over all runs: at the samples, and (continuous) between them
  std::string worst;
  // The guarantee the runs were judged by, and the two halves of min_margin: at the samples
  // (goal included) and strictly between them (dense, resolution tau / fine_substeps).
  bool continuous = true;
  double sampled_min_margin = 1e300;
  StepMargins between;  // smallest between-sample margin per part over all closed-loop runs
  std::string between_worst;
  int between_violations = 0;  // runs with a negative margin between the samples
  double dense_resolution_s = 0;  // time between two densely checked states
  int open_loop_runs = 0;
  int open_loop_violations = 0;
  double open_loop_min_margin = 1e300;
  std::string open_loop_worst;
  std::vector<OpenLoopRun> open_loop;  // one per open-loop run
  std::vector<KeptRun> kept;   // nominal, worst feedback run, paper scenarios closed and open loop
  double time_s = 0;
  double runs_time_s = 0;  // the closed-loop runs alone (wall clock, every thread)
  double runs_per_s() const { return runs_time_s > 0 ? runs / runs_time_s : 0.0; }
};

VerificationReport verify(const Problem& problem, const std::vector<NominalTrajectory>& nominal,
                          const std::vector<std::shared_ptr<const Controller>>& controllers,
                          const VerificationOptions& options = {});

// The scenarios run by verify(), in order (deterministic for a seed).
std::vector<Scenario> verification_scenarios(int runs, std::uint64_t seed);

}  // namespace marsyn
