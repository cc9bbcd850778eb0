#include "abcd_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <thread>
#include <tuple>

#include "controller_file.hpp"
#include "successor_cache.hpp"
#include "marsyn/memory_budget.hpp"
#include "marsyn/number_text.hpp"
#include "marsyn/param_set.hpp"

namespace marsyn::abcd {

namespace {

ParamSet<Options> declare() {
  using O = Options;
  using S = SuccessorOptions;
  // The enclosure's two ranges are checked as soon as each is read, the others after every
  // value is read: the order the messages have always come in.
  constexpr Checked on_read = Checked::on_read, last = Checked::last;
  ParamSet<O> s;
  s.integer("substeps", 1, 1000,
            "substeps of the sound enclosure over one sampling period (more: tighter boxes, slower)", last,
            &O::successor, &S::substeps);
  s.integer("taylor_terms", 4, 16, "matrix-exponential series terms before the rigorous tail bound", last,
            &O::successor, &S::taylor_terms);
  s.integer("picard_iterations", 1, 100, "a priori enclosure attempts before an input is dropped", last, &O::successor,
            &S::picard_iterations);
  s.add("prefilter", &O::prefilter, "true|false",
        "skip inputs whose RK4 centre image leaves the next tube before computing their box (work only)");
  s.integer("prefilter_substeps", 1, 1000, "RK4 substeps of the prefilter's centre image", last,
            &O::prefilter_substeps);
  s.integer("threads", 0, 256, "worker threads; 0: the run's thread option", last, &O::threads);
  s.integer("enclosure_substeps", 1, SuccessorBox::kMaxEncloseSubsteps,
            "boxes per sampling period enclosing the closed loop between samples (continuous-time guarantee; "
            "more: tighter)",
            on_read, &O::enclosure_substeps);
  s.integer("enclosure_block", 1, 64,
            "cells per block enclosed together between samples, along coordinates the field reads (fewer: "
            "tighter, slower)",
            on_read, &O::enclosure_block);
  return s;
}

}  // namespace

AbcdTracker::AbcdTracker(const Params& p) : base_(declared_once<declare>().parse(p)) {}

std::vector<ParamSpec> AbcdTracker::param_specs() { return declared_once<declare>().specs(); }

Options AbcdTracker::options_for(const TrackOptions& o) const {
  Options s = base_;
  int t = base_.threads > 0 ? base_.threads : o.threads;
  if (t <= 0) t = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  s.threads = t;
  s.memory_budget_bytes = o.memory_budget_bytes;
  s.collective = o.collective;
  s.progress = o.progress;
  s.stop = o.stop;
  return s;
}

TrackResult AbcdTracker::track(const TrackingProblem& problem, const TrackOptions& options) const {
  Options s = options_for(options);
  s.successor.tau = problem.tau;
  if (!s.hook) s.hook = dynamic_cast<const SuccessorBoundHook*>(problem.dynamics.get());
  return synthesize_track(problem, s);
}

TrackResult AbcdTracker::reach_avoid(const ReachAvoidProblem& problem, const TrackOptions& options) const {
  Options s = options_for(options);
  s.successor.tau = problem.tau;
  if (!s.hook) s.hook = dynamic_cast<const SuccessorBoundHook*>(problem.dynamics.get());
  return synthesize_reach_avoid(problem, s);
}

namespace {

bool has_grid(const AgentSpec& a) {
  return a.fields.value(kEtaX).size() == a.n() && a.fields.value(kEtaU).size() == a.m() && a.n() > 0;
}

// The first coordinate whose x0 cell leaves [x0 - eps, x0 + eps], or -1.
int x0_cell_defect(const AgentSpec& a) {
  const Eigen::VectorXd eta_x = a.fields.value(kEtaX);
  for (int i = 0; i < a.n(); ++i) {
    const CellBounds cell = x0_cell(a, eta_x, i);
    if (cell.lo < a.x0[i] - a.tube.eps[i] || cell.hi > a.x0[i] + a.tube.eps[i]) return i;
  }
  return -1;
}

// The grid field `name` times `factor` (a finer grid).
void scale_field(AgentSpec& a, const char* name, double factor) {
  if (AgentField* f = a.fields.find(name)) f->value *= factor;
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
  AssessRequest req;
  req.horizon = horizon;
  req.tau = tau;
  return assess(a, req);
}

TrackerAssessment AbcdTracker::assess(const AgentSpec& a, const AssessRequest& req) const {
  const int horizon = req.horizon;
  const int n = a.n(), m = a.m();
  const Eigen::VectorXd eta_x = a.fields.value(kEtaX), eta_u = a.fields.value(kEtaU);
  for (const auto& [field, size, what, eps] :
       {std::tuple{kEtaX, n, "the cell size of its state grid", true}, std::tuple{kEtaU, m, "the spacing of its input grid", false}}) {
    const Eigen::Index have = std::string(field) == kEtaX ? eta_x.size() : eta_u.size();
    if (have != size)
      return refuse(field, -1,
                    std::string("the abcd tracker needs '") + field + "', " + what + " (" + std::to_string(size) +
                        " positive numbers" +
                        (eps ? ", each at most eps, e.g. eps / 8 = " + list_text(a.tube.eps / 8, "[", "]") : "") +
                        "); give it or choose another tracker");
  }
  const auto names = a.dynamics ? a.dynamics->state_names() : std::vector<std::string>(n, "?");
  if (const int i = x0_cell_defect(a); i >= 0) {
    const CellBounds cell = x0_cell(a, eta_x, i);
    return refuse("eta_x", i,
                  std::string(a.x0_half(i) > 0 ? "the grid cells of the initial set x0 +- x0_radius" : "x0's grid cell") +
                      " [" + number_text(cell.lo) + ", " + number_text(cell.hi) + "] in '" + names[i] +
                      "' does not fit inside the tube [x0 - eps, x0 + eps] = [" + number_text(a.x0[i] - a.tube.eps[i]) +
                      ", " + number_text(a.x0[i] + a.tube.eps[i]) + "]; " +
                      (a.x0_half(i) > 0 ? "choose eta_x well below eps - x0_radius (" + number_text(a.tube.eps[i] - a.x0_half(i)) + ")"
                                        : "choose eta_x <= eps (" + number_text(a.tube.eps[i]) + ")"));
  }
  for (int i = 0; i < n; ++i) {
    const double cells = (a.state_bounds.hi[i] - a.state_bounds.lo[i]) / eta_x[i];
    if (!(cells <= kMaxGridCellsPerCoordinate))
      return refuse("eta_x", i,
                    "eta_x = " + number_text(eta_x[i]) + " makes " + number_text(cells) +
                        " grid cells across the state bounds in '" + names[i] + "'; at most " +
                        number_text(kMaxGridCellsPerCoordinate) + " are supported");
  }
  // Storage: a u16 per (tube cell, step), prefix sums over two steps' tubes, the input grid over
  // U. Tube cells per step: prod_i (floor(2 eps_i / eta_x_i) + 1) at most.
  double tube = 1, tube_upper = 1, work_cells = 1, inputs = 1;
  for (int i = 0; i < n; ++i) {
    const double c = std::floor(2 * a.tube.eps[i] / eta_x[i]);
    tube *= c + 1;
    tube_upper *= c;  // cells lying entirely inside one eps-box: at most floor(2 eps / eta)
    work_cells *= std::max(1.0, c);
  }
  for (int j = 0; j < m; ++j) inputs *= std::floor((a.input_bounds.hi[j] - a.input_bounds.lo[j]) / eta_u[j] + 1e-9) + 1;
  const double budget = req.memory_budget.bytes;
  const std::string& source = req.memory_budget.source;
  const double state_bytes = (static_cast<double>(horizon) + 1) * tube * 2 + 2 * tube * 8;
  if (!(state_bytes <= budget))
    return refuse("eta_x", -1,
                  "the tracker would need about " + format_bytes(state_bytes) + " for this agent (" +
                      number_text(tube, 3) + " tube cells per step x " + std::to_string(horizon + 1) +
                      " steps), more than the memory budget of " + format_bytes(budget) + " (" + source +
                      "); enlarge eta_x");
  const double input_bytes = inputs * (m + 1) * 8.0;
  if (!(input_bytes <= budget))
    return refuse("eta_u", -1,
                  "the tracker would need about " + format_bytes(input_bytes) + " for this agent's inputs (" +
                      number_text(inputs, 3) + " grid inputs over U), more than the memory budget of " +
                      format_bytes(budget) + " (" + source + "); enlarge eta_u");
  TrackerAssessment r;
  r.work_s = kSecondsPerStateInputPair * (static_cast<double>(horizon) + 1) * work_cells * inputs;
  // Working memory besides the tables: the successor cache (successor_cache.hpp), two open-
  // addressing maps (this step's entries and the last's) of at most one entry per (column, input)
  // of a step's tube, a column being a cell along the coordinates the field depends on; each map
  // at most half full, in powers of two, and a map's old slots beside the new while it grows.
  // An upper figure: the sweep stops at a column's first winning input (massif: drone1 of
  // multi_drone 3.9 MiB, this figure 3.9 MiB; the pendulum 15.7 MiB of 63 MiB).
  std::vector<bool> inv = a.dynamics ? a.dynamics->field_independent_of() : std::vector<bool>{};
  inv.resize(static_cast<std::size_t>(n), false);
  double columns = 1;
  for (int i = 0; i < n; ++i)
    if (!inv[static_cast<std::size_t>(i)]) columns *= std::floor(2 * a.tube.eps[i] / eta_x[i]) + 1;
  // (A map never holds fewer than 1024 slots.)
  const double slots = std::exp2(std::ceil(std::log2(std::max(1024.0, 2 * columns * inputs))));
  r.memory_bytes = state_bytes + input_bytes + 2.5 * slots * SuccessorTable::slot_bytes();
  // Kept: the table, each step's index box and offset, and the period enclosures (state and
  // workspace boxes, each vector a heap block: glibc's 8-byte header, 16-byte granules, 32 at
  // least; the list's room as push_back grew it, up to twice its size).
  auto block = [](double bytes) { return std::max(32.0, std::ceil((bytes + 8) / 16) * 16); };
  const double steps = std::max(1, horizon), enclosures = steps * base_.enclosure_substeps;
  r.kept_bytes = (steps + 1) * (tube * 2 + sizeof(IndexBox) + sizeof(std::int64_t)) +
                 enclosures * (2 * sizeof(PeriodEnclosure) + 2 * block(8.0 * n) + 2 * block(8.0 * std::max(n, 3)));
  r.summary = "<= " + number_text(tube_upper) + " tube cells/step, " + number_text(inputs) + " grid inputs";
  return r;
}

bool AbcdTracker::refine(AgentSpec& agent) const {
  if (!has_grid(agent)) return false;
  AgentSpec b = agent;
  scale_field(b, kEtaX, 0.75);
  scale_field(b, kEtaU, 0.75);
  if (x0_cell_defect(b) >= 0) return false;
  agent = b;
  return true;
}

namespace {
constexpr long kMaxLeverSubsteps = 64;
}  // namespace

std::vector<TrackerLever> AbcdTracker::levers(const AgentSpec& agent) const {
  std::vector<TrackerLever> out;
  const TrackFailure none;
  const std::vector<TrackFailureKind> grid{TrackFailureKind::EmptyWinningSet, TrackFailureKind::Unknown};
  // The sweep's work grows with the tube cells (eta_x^-n) and the grid inputs (eta_u^-m).
  const char* names[] = {"finer state grid", "finer input grid", "more substeps"};
  const double costs[] = {std::pow(1 / 0.75, agent.n()), std::pow(1 / 0.75, agent.m()), 2.0};
  for (int i = 0; i < 3; ++i) {
    AgentSpec b = agent;
    if (apply_lever(names[i], none, b)) out.push_back({names[i], grid, costs[i]});
  }
  return out;
}

bool AbcdTracker::apply_lever(const std::string& name, const TrackFailure& failure, AgentSpec& agent) const {
  (void)failure;
  if (!has_grid(agent)) return false;
  AgentSpec b = agent;
  if (name == "finer state grid") scale_field(b, kEtaX, 0.75);
  else if (name == "finer input grid") scale_field(b, kEtaU, 0.75);
  else if (name == "more substeps") {
    const long sub = b.tracker.params.integer("substeps", base_.successor.substeps);
    if (sub * 2 > kMaxLeverSubsteps) return false;
    b.tracker.params.set("substeps", sub * 2);
  } else if (name == "refine") {
    return refine(agent);
  } else {
    return false;
  }
  if (x0_cell_defect(b) >= 0) return false;
  agent = b;
  return true;
}

std::shared_ptr<const Controller> AbcdTracker::read_controller(const std::string& path) const {
  return abcd::read_controller(path);
}

}  // namespace marsyn::abcd
