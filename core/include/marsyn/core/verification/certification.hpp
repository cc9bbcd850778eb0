#pragma once
// The certifier (architecture: between tracking and closed-loop verification): the safety part
// of the specification checked on the trackers' period enclosures themselves, so that a problem
// is VERIFIED for every time t in [0, T tau], not only at the samples (docs/soundness.md §10).
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "marsyn/core/planning/mission.hpp"
#include "marsyn/problem.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn {

struct CertifiedPart {
  double margin = std::numeric_limits<double>::infinity();  // sound lower bound; inf: no such part
  std::string where;  // e.g. "obstacle block vs drone3"
  int step = -1;      // the period [step tau, (step + 1) tau]
};

struct CertificationReport {
  bool certified = false;
  std::string message;  // one line
  CertifiedPart state_bounds, obstacle, collision, formation;
  // Mission stages (docs/tasks.md): each region at its scheduled visit knots on the enclosures
  // of the sampling instants, and between those knots on every part while the stage dwells.
  CertifiedPart stage;
  std::vector<planning::StageVisit> stages;
  double min_margin = std::numeric_limits<double>::infinity();
  std::vector<int> failing_agents;  // indices of agents in a part with a negative margin
  // Every requirement with a negative margin on the enclosures, by the planning constraint's
  // name (planning::AssemblyOptions::extra), with its most negative margin.
  std::map<std::string, double> shortfalls;
  long long enclosures = 0;
  double time_s = 0.0;
};

// Every agent's controller must carry period enclosures covering steps 0..T-1; pairs of agents
// are compared on enclosures of overlapping parts of the same period (the agents share one
// clock: every controller starts at t = 0 and switches at t = k tau).
CertificationReport certify(const Problem& problem, const std::vector<std::shared_ptr<const Controller>>& controllers);

}  // namespace marsyn
