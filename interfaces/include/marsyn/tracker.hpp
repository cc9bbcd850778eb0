#pragma once
// Step 3 of the method: a per-agent feedback controller C(x, k) that keeps the agent inside the
// eps-box around its nominal state at every step k, for every disturbance in W (Phi_track,
// paper eq. 1). A Tracker is an immutable model; track() is const and re-entrant, so agents can
// be processed in parallel.
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "marsyn/collective.hpp"
#include "marsyn/controller_export.hpp"
#include "marsyn/export.hpp"
#include "marsyn/memory_budget.hpp"
#include "marsyn/problem.hpp"

namespace marsyn {

enum class TrackerStatus {
  ControllerFound,  // a verified controller (abcd: x_0's cell is winning; funnel: the initial set is in V_0)
  NoController,   // the tube admits no controller at this eps / eta
  InvalidInput,
  ResourceLimit,  // memory or time budget exceeded
};

inline const char* to_string(TrackerStatus s) {
  switch (s) {
    case TrackerStatus::ControllerFound: return "controller";
    case TrackerStatus::NoController: return "no controller";
    case TrackerStatus::InvalidInput: return "invalid input";
    case TrackerStatus::ResourceLimit: return "resource limit";
  }
  return "?";
}

enum class ControlStatus { Ok, OutsideDomain, OutsideHorizon };

// Where the closed loop can be during part of a sampling period (the continuous-time guarantee,
// docs/soundness.md "Continuous time"): for every initial state in a winning cell of step 0,
// every measurable disturbance in [-W, W] and every t in [t0, t1] (seconds from the start of the
// horizon, t0 >= k tau and t1 <= (k+1) tau for the step k it belongs to), the state lies in
// `state` and the agent's workspace point in `workspace` (2 intervals). A step's n enclosures
// split its period into n equal parts, part p covering [k + p/n, k + (p+1)/n] tau (the
// certifier compares agents' parts by index and refuses any other split).
struct PeriodEnclosure {
  int step = 0;
  double t0 = 0.0, t1 = 0.0;
  Box state;
  Box workspace;
};

// A synthesized controller. input() answers in O(1).
class Controller {
 public:
  virtual ~Controller() = default;
  virtual int state_dim() const = 0;
  virtual int input_dim() const = 0;
  virtual int horizon() const = 0;  // steps k = 0..horizon(); time-invariant controllers: -1
  virtual ControlStatus input(const double* x, int k, double* u) const = 0;
  virtual void write(const std::string& path) const = 0;  // throws std::runtime_error on I/O failure
  // Sound enclosures of the closed loop between the samples, ordered by time, covering
  // [0, horizon() tau]; empty when the tracker gives no continuous-time guarantee.
  virtual const std::vector<PeriodEnclosure>& period_enclosures() const = 0;
  // Writes the controller in another format (controller_export.hpp, docs/deploy.md). Failures
  // (unsupported format, bad prefix, I/O) are reported in the result, never thrown.
  virtual ExportResult export_to(const ExportRequest& request) const {
    ExportResult r;
    r.message = "this controller does not support export";
    (void)request;
    return r;
  }
};

// Optional model-specific successor bound. A Dynamics implementation may also derive from this
// class; trackers that find it (dynamic_cast) intersect their own sound successor box with the
// model's, so the hook can only tighten it and must itself be sound: for every state in `cell`
// (n intervals), the constant input u, and every measurable disturbance with values in [-w, w],
// the state after tau lies in [lo, hi]. Returns false when it cannot bound the case.
class MARSYN_EXPORT SuccessorBoundHook {  // exported: found by dynamic_cast across plugin libraries
 public:
  virtual ~SuccessorBoundHook() = default;
  virtual bool successor(const Interval* cell, const double* u, const double* w, double tau, double* lo,
                         double* hi) const = 0;
};

struct TrackingProblem {
  std::string agent;
  std::shared_ptr<const Dynamics> dynamics;
  NominalTrajectory nominal;
  TubeParams tube;  // the agent's, unchanged
  AgentFields fields;  // the agent's tracker-owned fields (abcd: its grid), unchanged
  Box input_bounds;
  Box state_bounds;
  double tau = 0.1;
  Workspace workspace;  // the agent's workspace map, for the workspace part of period enclosures
  // The stated initial set's half-widths (AgentSpec::x0_radius): the controller must accept every
  // state of nominal.x[0] +- initial_radius at step 0, and its guarantee must hold from each.
  // Empty: nominal.x[0] alone (a tracker may still start from a box of its own around it).
  Eigen::VectorXd initial_radius;
};

// Whole-domain mode (global ABCD baseline): reach `target` while staying in `safe`, over the box
// `domain`, with a time-invariant controller, on the grid eta_x, eta_u over the product (core
// stacks the agents' own grids, docs/architecture.md).
struct ReachAvoidProblem {
  std::shared_ptr<const Dynamics> dynamics;
  Box domain, safe, target;
  Eigen::VectorXd eta_x, eta_u, w;
  Box input_bounds;
  double tau = 0.1;
  // Optional: true when the closed cell [lo, hi] (state_dim() numbers each) may meet the avoid
  // set; such cells are never winning unless in the target. It must over-approximate (answer
  // true when unsure) for the controller to be sound. Declared last so that a tracker built
  // without it never reads it.
  std::function<bool(const double* lo, const double* hi)> unsafe;
};

// A figure one tracker reports about a synthesis beyond the ones every tracker fills (OMPL's
// planner progress properties): core, the CLI, result.json and Python print what the tracker
// declares, by name, and keep no list of any tracker's figures. A vector is one count per step
// k = 0, 1, ... of the tracking horizon.
struct TrackerFigure {
  using Value = std::variant<bool, long long, double, std::vector<long long>>;
  std::string name;   // the key in result.json and Python, e.g. "tube_cells"; unique in a result
  std::string label;  // how the CLI prints it, e.g. "tube cells"
  Value value;
};

struct TrackerStats {
  double state_input_pairs = 0;  // N_l as in the paper: the state-input pairs the tracker abstracts
  long long boxes_computed = 0;  // successor boxes (or enclosure steps) actually computed
  double abstraction_time_s = 0.0;
  double synthesis_time_s = 0.0;
  long long peak_memory_bytes = 0;
  double enclosure_time_s = 0.0;  // period enclosures (continuous time), after the synthesis
  int enclosure_substeps = 0;     // boxes per sampling period; 0: no enclosures
  std::vector<TrackerFigure> figures;  // the tracker's own, in the order it sets them
  // Per state coordinate, the largest distance from the nominal that the closed loop reaches at
  // the samples from the initial set; empty: the tracker does not say, and core reads the period
  // enclosures instead. A tracker whose stored sets are wider than the reachable tube on purpose
  // (the funnel's invariant sets) states it, or `eps: auto` narrows to those sets and not to the
  // tube the controller keeps (docs/search.md, "eps: auto").
  std::vector<double> tube_kept;

  // Sets the figure `name` (appended the first time, replaced after).
  void set(const std::string& name, const std::string& label, TrackerFigure::Value value) {
    for (auto& f : figures)
      if (f.name == name) {
        f.label = label;
        f.value = std::move(value);
        return;
      }
    figures.push_back({name, label, std::move(value)});
  }
  // The figure `name` as a T, or `fallback` when the tracker did not set it (or set another type).
  template <class T>
  T get(std::string_view name, T fallback = T{}) const {
    for (const auto& f : figures)
      if (f.name == name)
        if (const T* v = std::get_if<T>(&f.value)) return *v;
    return fallback;
  }
};

struct TrackOptions {
  int threads = 0;  // 0: hardware concurrency
  // The run's budget (memory_budget.hpp), the one the assessment judged: the front end sets it.
  double memory_budget_bytes = machine_memory_budget().bytes;
  // The ranks sharing this one agent's synthesis (docs/mpi.md): every rank of the group calls
  // track() with the same problem and options, and each returns the same result. nullptr or a
  // group of one: this process alone. A tracker that cannot split its work may ignore it (each
  // rank then computes the whole agent).
  const Collective* collective = nullptr;
  // Called from the calling thread as the synthesis advances (abcd: after each backward step,
  // done of total steps); may be empty.
  std::function<void(int done, int total)> progress;
  // The run's stop request (its time limit, SIGINT, SIGTERM): a tracker polls it now and then
  // (abcd: every few dozen columns of its sweep; funnel: every step of a verification), from any
  // of its threads, and when it says true returns at once with TrackerStatus::ResourceLimit (a
  // message that says it was stopped), so that a limit is kept to within a fraction of a second
  // instead of a whole synthesis. Not polled where ranks share one agent's work (`collective` of more than
  // one rank), whose ranks must leave together. May be empty.
  std::function<bool()> stop;
};

// Why a tracker found no controller, as the outer search reads it to choose its next lever
// (docs/search.md): which coordinate left the tube at which step and by how much, or from which
// step the winning set is empty, and whether the nominal's inputs sat at a bound of U.
enum class TrackFailureKind {
  Unknown,          // no structured reason (the message says what happened)
  TubeMiss,         // the verified enclosure leaves the eps-tube in `coordinate` at `step` by `amount`
  EmptyWinningSet,  // a grid tracker's winning set is empty from `step` backwards
};

inline const char* to_string(TrackFailureKind k) {
  switch (k) {
    case TrackFailureKind::Unknown: return "unknown";
    case TrackFailureKind::TubeMiss: return "tube miss";
    case TrackFailureKind::EmptyWinningSet: return "empty winning set";
  }
  return "?";
}

struct TrackFailure {
  TrackFailureKind kind = TrackFailureKind::Unknown;
  int coordinate = -1;  // TubeMiss: the state coordinate; -1: not one coordinate
  int step = -1;        // the step of the failure; -1: unknown
  double amount = 0.0;  // TubeMiss: by how much the enclosure leaves the tube (state units)
  // The share of the steps (0..1) on which the tracker found some input saturated at a bound of
  // U; core also measures the nominal's own share (docs/search.md, "tighten U for the nominal").
  double input_saturation = 0.0;
  // TubeMiss: the enclosure is narrower than the tube there, but its centre has left the nominal
  // by more than its half-width (typically inputs held at a bound of U): a tighter enclosure does
  // not help, a nominal that leaves the feedback room (U tightened for it) may.
  bool off_centre = false;
  // TubeMiss: per state coordinate, the largest share of eps that the verified sets' distance
  // from the nominal reached before the miss (1 at the tube's edge); empty when the tracker cannot
  // say. The search widens the coordinates at the edge together with the missed one: a
  // 12-state drone that misses in vx is at 0.998 of eps in vy, and widening vx alone moves the
  // miss there in the next round.
  std::vector<double> tube_use;
};

struct TrackResult {
  TrackerStatus status = TrackerStatus::InvalidInput;
  std::shared_ptr<const Controller> controller;  // set iff status == ControllerFound
  TrackerStats stats;
  std::string message;
  TrackFailure failure;  // status == NoController: why, as far as the tracker can say
};

// One of a tracker's own knobs (Remark 2) as the outer search sees it: its name, the failures it
// addresses and its estimated cost, the tracking work after over before (a finer grid costs more).
struct TrackerLever {
  std::string name;                          // e.g. "finer state grid"; unique within the tracker
  std::vector<TrackFailureKind> addresses;   // the failure kinds it is worth trying for
  double cost_factor = 1.0;
};

// What a tracker says about one agent before any plan exists (`marsyn check`, `tracker: auto`,
// the per-agent fan-out). Each tracker judges the agent by its own rules (abcd: its grid and
// x_0's cell; funnel: its initial set), so core keeps no copy of any tracker's conventions.
struct TrackerAssessment {
  bool ok = true;
  std::string field;    // the agent's field at fault when !ok ("eps", a field or a parameter of the tracker)
  int coordinate = -1;  // the state or input coordinate at fault; -1: the whole field
  std::string message;  // what is wrong and what would do, when !ok
  // Estimated tracking cost, to rank trackers and to spread agents over threads or ranks: seconds
  // of one core (order of magnitude only) and the synthesis's peak working memory in bytes.
  double work_s = 0.0;
  double memory_bytes = 0.0;
  // What the controller keeps once found (its tables, sets and enclosures, with the allocator's
  // overhead), an upper estimate: the tracking stage's memory is every agent's kept bytes plus a
  // synthesis's working memory per thread (`check`, docs/problem-format.md "Resources"). 0: not
  // stated (core then counts memory_bytes).
  double kept_bytes = 0.0;
  std::string summary;  // one line for `marsyn check`, e.g. "<= 1600 tube cells per step"
};

// What assess() is asked: the horizon (steps) and period (seconds) of the tracking to come, and
// the run's memory budget, which the assessment's estimate is judged against (the same value
// reaches track() as TrackOptions::memory_budget_bytes).
struct AssessRequest {
  int horizon = 0;
  double tau = 0.1;
  MemoryBudget memory_budget = machine_memory_budget();
};

// An agent-level field a tracker owns (AgentSpec::fields, e.g. abcd's eta_x): its name, whether
// it holds one number per input (else one per state), and what it means. The loader accepts it in
// every agent (and `defaults`) as positive numbers or `auto`.
struct AgentFieldSpec {
  std::string name;
  bool per_input = false;
  std::string doc;
};

// How an agent's tube just changed, for Tracker::follow_tube.
enum class TubeChange {
  Set,       // eps given or derived (the loader, the search's auto eps): automatic fields follow it
  Narrowed,  // a search lever narrowed eps: every field is kept within the narrower tube
};

// What a tracker can do beyond track(), declared so that core asks the tracker rather than
// knowing which one does what.
struct TrackerCapabilities {
  bool reach_avoid = false;  // whole-domain reach_avoid() (the global baseline)
  // track() honours TrackingProblem::initial_radius: its controller accepts, and its guarantee
  // holds from, every state of the stated initial set at step 0. Agents that state one are not
  // given to a tracker without it.
  bool initial_set = false;
  // track() reads the state-dependent disturbance (TubeParams::w_base, w_growth) and its
  // guarantee holds under W(x, u). A tracker without it reads TubeParams::w, the largest W over X
  // and U, which is sound and only more cautious.
  bool state_dependent_disturbance = false;
};

class Tracker {
 public:
  virtual ~Tracker() = default;
  virtual std::string name() const = 0;
  virtual TrackerCapabilities capabilities() const { return {}; }
  virtual TrackResult track(const TrackingProblem& problem, const TrackOptions& options) const = 0;
  virtual TrackResult reach_avoid(const ReachAvoidProblem&, const TrackOptions&) const {
    TrackResult r;
    r.message = name() + " does not support whole-domain reach-avoid";
    return r;
  }
  // Before planning: can this tracker work on the agent over request.horizon steps of
  // request.tau, within request.memory_budget, and at what cost? Core calls this form. The
  // default asks the older form below, for trackers that judge no memory budget.
  virtual TrackerAssessment assess(const AgentSpec& agent, const AssessRequest& request) const {
    return assess(agent, request.horizon, request.tau);
  }
  // The older form, without the budget; the default accepts everything at no estimated cost.
  virtual TrackerAssessment assess(const AgentSpec& agent, int horizon, double tau) const {
    (void)agent, (void)horizon, (void)tau;
    return {};
  }
  // The agent-level fields this tracker owns (abcd: its grid); none by default.
  virtual std::vector<AgentFieldSpec> agent_fields() const { return {}; }
  // Brings the fields this tracker owns (agent.fields) in step with agent.tube after `change`
  // (abcd: an automatic grid from eps and U; a grid no coarser than a narrowed eps). Core calls it
  // on every installed tracker, whichever tracks the agent, so that the fields mean the same under
  // a fallback. Returns the rule that gave the automatic fields their values (empty: none).
  virtual std::string follow_tube(AgentSpec& agent, TubeChange change) const {
    (void)agent, (void)change;
    return {};
  }
  // Remarks on the fields this tracker owns that do not stop loading (`marsyn check`), each a
  // sentence with its numbers, about the agent whichever tracker it has.
  virtual std::vector<std::string> field_warnings(const AgentSpec& agent) const {
    (void)agent;
    return {};
  }
  // Remark 2, the tracker's own knobs: after "no controller" at the agent's eps, change what this
  // tracker owns on the agent, never its tube: its parameters (agent.tracker.params; funnel: the
  // enclosure and the weights) or its fields (agent.fields; abcd: finer grids). Returns true, or
  // false when nothing is left to refine.
  virtual bool refine(AgentSpec& agent) const {
    (void)agent;
    return false;
  }
  // The knobs this tracker can still turn on `agent` (those whose change is possible from its
  // current parameters), best first. The default offers refine() as one lever for every kind.
  virtual std::vector<TrackerLever> levers(const AgentSpec& agent) const {
    AgentSpec copy = agent;
    if (!refine(copy)) return {};
    return {{"refine", {TrackFailureKind::Unknown, TrackFailureKind::TubeMiss, TrackFailureKind::EmptyWinningSet}, 1.0}};
  }
  // Turns the lever `name` (one of levers(agent)) for the failure; false, agent unchanged, when it
  // cannot. The default turns "refine" through refine().
  virtual bool apply_lever(const std::string& name, const TrackFailure& failure, AgentSpec& agent) const {
    (void)failure;
    return name == "refine" && refine(agent);
  }
  // Reads a controller file written by this tracker; throws std::runtime_error on a corrupt or
  // mismatched file.
  virtual std::shared_ptr<const Controller> read_controller(const std::string& path) const = 0;
};

}  // namespace marsyn
