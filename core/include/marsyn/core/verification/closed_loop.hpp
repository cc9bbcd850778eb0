#pragma once
// Simulation of all agents together, each under its own controller C_i(x_i, k) (local state and
// time only: no communication) or open loop under its nominal inputs, with disturbances drawn
// by a scenario. Integration is fine RK4, independent of any abstraction.
#include <cstdint>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "marsyn/core/verification/spec_monitor.hpp"
#include "marsyn/problem.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn {

enum class DisturbanceMode {
  None,
  ConstantVertex,    // one vertex of W per agent, held for the whole run
  PaperConstant,     // agent i gets (-1)^i W (or its negation), held: the paper's Figs. 9-11
  UniformRandom,     // uniform in W, redrawn every sampling period
  VertexSwitching,   // a random vertex of W, redrawn every sampling period
  Adversarial,       // re-chosen at every integration substep: the vertex of W pushing the agent's
                     // workspace point toward its nearest obstacle or agent (position
                     // coordinates of a linear workspace map; other coordinates a random vertex)
};

const char* to_string(DisturbanceMode m);
// Parses "none", "vertex", "paper", "uniform", "switching", "adversarial"; throws
// std::invalid_argument.
DisturbanceMode parse_disturbance_mode(const std::string& s);

struct Scenario {
  DisturbanceMode mode = DisturbanceMode::None;
  std::uint64_t seed = 0;
  int variant = 0;  // PaperConstant: sign pattern; ConstantVertex: which vertices
};

struct ClosedLoopRun {
  std::vector<Eigen::VectorXd> states;  // product states x_0..x_T
  int outside_domain_agent = -1;        // first agent whose controller had no input
  int outside_domain_step = -1;
  double max_tube_excess = 0.0;  // max over agents, steps, coords of |x - nominal| / eps (<= 1 inside the tube)
  // Dense in time (setup.between set): the real spec at every integration substep strictly
  // between the samples (resolution tau / fine_substeps), smallest margin per part, and the
  // time [s] of the smallest overall.
  StepMargins between;
  double between_worst_t = -1.0;
  std::string between_worst;
  // setup.between set: the real spec at the samples, goal included, as between->evaluate(states)
  // gives it (no per_step), checked while running so that the states need not be kept.
  SpecEvaluation sampled;
  // setup.keep_dense: the product state at every substep (samples included) and its time.
  std::vector<double> dense_t;
  std::vector<Eigen::VectorXd> dense_states;
  std::vector<StepMargins> dense_margins;  // setup.keep_dense: the spec at each of dense_states (step()'s values)
};

struct SimulationSetup {
  const Problem* problem = nullptr;
  std::vector<NominalTrajectory> nominal;                // per agent
  std::vector<std::shared_ptr<const Controller>> controllers;  // per agent; empty: open loop
  int fine_substeps = 20;                                // RK4 steps per sampling period
  const SpecMonitor* between = nullptr;  // evaluate the spec between the samples (dense) when set
  bool keep_dense = false;
  bool keep_states = true;  // ClosedLoopRun::states (a verification run needs only its margins)
  // The reference the broad phase is tested and timed against: every requirement at every
  // substep (SpecMonitor::step) and the adversary's search over every obstacle and agent.
  bool all_pairs = false;
};

ClosedLoopRun simulate(const SimulationSetup& setup, const Scenario& scenario);
// Up to Lanes::kWidth runs at once (lanes.hpp: one integrator call per agent and substep for all
// of them); run r is what simulate(setup, scenarios[r]) gives, to the last bit.
std::vector<ClosedLoopRun> simulate(const SimulationSetup& setup, std::span<const Scenario> scenarios);

}  // namespace marsyn
