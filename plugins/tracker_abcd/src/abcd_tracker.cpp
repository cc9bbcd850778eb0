#include "abcd_tracker.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <thread>
#include <tuple>

#include "controller_file.hpp"
#include "marsyn/memory_budget.hpp"

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
  s.collective = o.collective;
  s.progress = o.progress;
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

namespace {

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string g(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

std::string vec(const Eigen::VectorXd& v) {
  std::string s = "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) s += (i ? ", " : "") + fmt(v[i]);
  return s + "]";
}

bool has_grid(const AgentSpec& a) {
  return a.eta_x.size() == a.n() && a.eta_u.size() == a.m() && a.n() > 0;
}

// The first coordinate whose x0 cell leaves [x0 - eps, x0 + eps], or -1.
int x0_cell_defect(const AgentSpec& a) {
  for (int i = 0; i < a.n(); ++i) {
    const CellBounds cell = x0_cell(a, i);
    if (cell.lo < a.x0[i] - a.eps[i] || cell.hi > a.x0[i] + a.eps[i]) return i;
  }
  return -1;
}

TrackerAssessment refuse(const std::string& field, int coordinate, const std::string& message) {
  TrackerAssessment r;
  r.ok = false;
  r.field = field;
  r.coordinate = coordinate;
  r.message = message;
  return r;
}

}  // namespace

TrackerAssessment AbcdTracker::assess(const AgentSpec& a, int horizon, double tau) const {
  (void)tau;
  const int n = a.n(), m = a.m();
  for (const auto& [field, size, what, eps] :
       {std::tuple{"eta_x", n, "the cell size of its state grid", true}, std::tuple{"eta_u", m, "the spacing of its input grid", false}}) {
    const Eigen::Index have = std::string(field) == "eta_x" ? a.eta_x.size() : a.eta_u.size();
    if (have != size)
      return refuse(field, -1,
                    std::string("the abcd tracker needs '") + field + "', " + what + " (" + std::to_string(size) +
                        " positive numbers" + (eps ? ", each at most eps, e.g. eps / 8 = " + vec(a.eps / 8) : "") +
                        "); give it or choose another tracker");
  }
  const auto names = a.dynamics ? a.dynamics->state_names() : std::vector<std::string>(n, "?");
  if (const int i = x0_cell_defect(a); i >= 0) {
    const CellBounds cell = x0_cell(a, i);
    return refuse("eta_x", i,
                  "x0's grid cell [" + fmt(cell.lo) + ", " + fmt(cell.hi) + "] in '" + names[i] +
                      "' does not fit inside the tube [x0 - eps, x0 + eps] = [" + fmt(a.x0[i] - a.eps[i]) + ", " +
                      fmt(a.x0[i] + a.eps[i]) + "]; choose eta_x <= eps (" + fmt(a.eps[i]) + ")");
  }
  for (int i = 0; i < n; ++i) {
    const double cells = (a.state_bounds.hi[i] - a.state_bounds.lo[i]) / a.eta_x[i];
    if (!(cells <= kMaxGridCellsPerCoordinate))
      return refuse("eta_x", i,
                    "eta_x = " + fmt(a.eta_x[i]) + " makes " + fmt(cells) + " grid cells across the state bounds in '" +
                        names[i] + "'; at most " + fmt(kMaxGridCellsPerCoordinate) + " are supported");
  }
  // Storage: a u16 per (tube cell, step), prefix sums over two steps' tubes, the input grid over
  // U. Tube cells per step: prod_i (floor(2 eps_i / eta_x_i) + 1) at most.
  double tube = 1, tube_upper = 1, work_cells = 1, inputs = 1;
  for (int i = 0; i < n; ++i) {
    const double c = std::floor(2 * a.eps[i] / a.eta_x[i]);
    tube *= c + 1;
    tube_upper *= c;  // cells lying entirely inside one eps-box: at most floor(2 eps / eta)
    work_cells *= std::max(1.0, c);
  }
  for (int j = 0; j < m; ++j) inputs *= std::floor((a.input_bounds.hi[j] - a.input_bounds.lo[j]) / a.eta_u[j] + 1e-9) + 1;
  std::string source;
  const double budget = memory_budget_from_environment(&source);
  const double state_bytes = (static_cast<double>(horizon) + 1) * tube * 2 + 2 * tube * 8;
  if (!(state_bytes <= budget))
    return refuse("eta_x", -1,
                  "the tracker would need about " + format_bytes(state_bytes) + " for this agent (" + g(tube) +
                      " tube cells per step x " + std::to_string(horizon + 1) + " steps), more than the memory budget of " +
                      format_bytes(budget) + " (" + source + "); enlarge eta_x");
  const double input_bytes = inputs * (m + 1) * 8.0;
  if (!(input_bytes <= budget))
    return refuse("eta_u", -1,
                  "the tracker would need about " + format_bytes(input_bytes) + " for this agent's inputs (" + g(inputs) +
                      " grid inputs over U), more than the memory budget of " + format_bytes(budget) + " (" + source +
                      "); enlarge eta_u");
  TrackerAssessment r;
  r.work_s = kSecondsPerStateInputPair * (static_cast<double>(horizon) + 1) * work_cells * inputs;
  r.memory_bytes = state_bytes + input_bytes;
  r.summary = "<= " + fmt(tube_upper) + " tube cells/step, " + fmt(inputs) + " grid inputs";
  return r;
}

bool AbcdTracker::refine(AgentSpec& agent) const {
  if (!has_grid(agent)) return false;
  AgentSpec b = agent;
  b.eta_x *= 0.75;
  b.eta_u *= 0.75;
  if (x0_cell_defect(b) >= 0) return false;
  agent = b;
  return true;
}

std::shared_ptr<const Controller> AbcdTracker::read_controller(const std::string& path) const {
  return abcd::read_controller(path);
}

}  // namespace marsyn::abcd
