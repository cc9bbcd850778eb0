#include "marsyn/core/tracking/global_abcd.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "marsyn/core/tracking/product_dynamics.hpp"
#include "marsyn/scalar.hpp"
#include "marsyn/stopwatch.hpp"
#include "marsyn/number_text.hpp"

namespace marsyn {
namespace {

// Smallest gap between two closed intervals (0 when they meet).
double gap(double alo, double ahi, double blo, double bhi) { return std::max({0.0, blo - ahi, alo - bhi}); }

double box_distance(const double* a, const double* b, Norm norm) {  // boxes as {xlo, ylo, xhi, yhi}
  const double gx = gap(a[0], a[2], b[0], b[2]), gy = gap(a[1], a[3], b[1], b[3]);
  return norm == Norm::Inf ? std::max(gx, gy) : std::sqrt(gx * gx + gy * gy);
}

}  // namespace

std::function<bool(const double*, const double*)> product_unsafe(const Problem& pb) {
  std::vector<std::array<double, 4>> obstacle_boxes;
  for (const auto& o : pb.obstacles) {
    std::array<double, 4> b{1e300, 1e300, -1e300, -1e300};
    for (const auto& v : o.vertices) {
      b[0] = std::min(b[0], v.x());
      b[1] = std::min(b[1], v.y());
      b[2] = std::max(b[2], v.x());
      b[3] = std::max(b[3], v.y());
    }
    obstacle_boxes.push_back(b);  // contains the polygon: distances to it are never larger
  }
  return [&pb, obstacle_boxes, layout = ProductLayout(pb)](const double* lo, const double* hi) {
    std::vector<std::array<double, 4>> ws;  // per body slot (an agent's bodies read its state)
    for (int k = 0; k < pb.body_count(); ++k) {
      const AgentSpec& a = pb.body_spec(k);
      const int off = layout.state[static_cast<std::size_t>(pb.body_agent(k))];
      std::vector<Interval> x(a.n());
      for (int i = 0; i < a.n(); ++i) x[i] = Interval(lo[off + i], hi[off + i]);
      Interval p[kMaxWorkspaceDim];  // x-y only in 3-D: never farther than in space (conservative)
      workspace_point<Interval>(*a.dynamics, a.workspace, x.data(), p);
      ws.push_back({p[0].lower(), p[1].lower(), p[0].upper(), p[1].upper()});
    }
    for (std::size_t i = 0; i < ws.size(); ++i)
      for (const auto& o : obstacle_boxes)
        if (box_distance(ws[i].data(), o.data(), pb.delta_norm) < pb.obstacle_clearance(static_cast<int>(i))) return true;
    if (pb.pairwise_collision)
      for (std::size_t i = 0; i < ws.size(); ++i)
        for (std::size_t j = i + 1; j < ws.size(); ++j)
          if (pb.body_agent(static_cast<int>(i)) != pb.body_agent(static_cast<int>(j)) &&
              box_distance(ws[i].data(), ws[j].data(), pb.delta_norm) < pb.pair_clearance(static_cast<int>(i), static_cast<int>(j)))
            return true;
    return false;
  };
}

GlobalAbcdRun run_global_abcd(const Problem& pb, const Tracker& tracker, int threads, double budget) {
  const Stopwatch clock;
  GlobalAbcdRun run;
  ReachAvoidProblem rp;
  rp.dynamics = std::make_shared<ProductDynamics>(pb.agents);
  const int n = pb.product_state_dim(), m = pb.product_input_dim();
  rp.domain = {Eigen::VectorXd(n), Eigen::VectorXd(n)};
  rp.target = rp.domain;
  rp.eta_x.resize(n);
  rp.w.resize(n);
  rp.eta_u.resize(m);
  rp.input_bounds = {Eigen::VectorXd(m), Eigen::VectorXd(m)};
  const ProductLayout layout(pb);
  for (std::size_t i = 0; i < pb.agents.size(); ++i) {
    const AgentSpec& a = pb.agents[i];
    const int xo = layout.state[i], uo = layout.input[i];
    rp.domain.lo.segment(xo, a.n()) = a.state_bounds.lo;
    rp.domain.hi.segment(xo, a.n()) = a.state_bounds.hi;
    rp.target.lo.segment(xo, a.n()) = a.goal.lo;
    rp.target.hi.segment(xo, a.n()) = a.goal.hi;
    rp.eta_x.segment(xo, a.n()) = a.fields.value(kStateGridField);
    rp.w.segment(xo, a.n()) = a.tube.w;
    rp.eta_u.segment(uo, a.m()) = a.fields.value(kInputGridField);
    rp.input_bounds.lo.segment(uo, a.m()) = a.input_bounds.lo;
    rp.input_bounds.hi.segment(uo, a.m()) = a.input_bounds.hi;
  }
  rp.safe = rp.domain;
  rp.tau = pb.tau;
  rp.unsafe = product_unsafe(pb);
  TrackOptions to;
  to.threads = threads;
  to.memory_budget_bytes = budget;
  const TrackResult r = tracker.reach_avoid(rp, to);
  run.boxes_computed = r.stats.boxes_computed;
  if (r.status == TrackerStatus::ControllerFound && r.controller) {
    Eigen::VectorXd x0(n), u(m);
    const ProductLayout layout(pb);
    for (std::size_t i = 0; i < pb.agents.size(); ++i) x0.segment(layout.state[i], pb.agents[i].n()) = pb.agents[i].x0;
    run.initial_state_winning = r.controller->input(x0.data(), 0, u.data()) == ControlStatus::Ok;
    run.status = run.initial_state_winning ? "controller: x0 winning" : "controller, but x0 is not winning";
    // A baseline for comparison, never a deployed controller: it judges the point x0 alone.
    if (std::any_of(pb.agents.begin(), pb.agents.end(), [](const AgentSpec& a) { return a.x0_radius.size() > 0; }))
      run.status += " (the baseline tests x0 alone, not the stated initial sets)";
  } else {
    run.status = std::string(to_string(r.status)) + (r.message.empty() ? "" : ": " + r.message);
  }
  run.time_s = clock.seconds();
  return run;
}

GlobalAbcdEstimate estimate_global_abcd(const Problem& pb) {
  GlobalAbcdEstimate g;
  for (const auto& a : pb.agents)
    if (a.fields.value(kStateGridField).size() != a.n() || a.fields.value(kInputGridField).size() != a.m()) {
      g.status = "skipped: " + a.name + " has no eta_x and eta_u (the baseline abstracts the product on the agents' grids)";
      return g;
    }
  double pairs = 1;
  for (const auto& a : pb.agents) {
    const Eigen::VectorXd eta_x = a.fields.value(kStateGridField), eta_u = a.fields.value(kInputGridField);
    for (int i = 0; i < a.n(); ++i) pairs *= std::ceil((a.state_bounds.hi[i] - a.state_bounds.lo[i]) / eta_x[i]);
    for (int j = 0; j < a.m(); ++j) pairs *= std::floor((a.input_bounds.hi[j] - a.input_bounds.lo[j]) / eta_u[j] + 1e-9) + 1;
  }
  g.state_input_pairs = pairs;
  // A SCOTS-style transition table stores at least one 64-bit successor range per pair.
  g.memory_bytes_estimate = pairs * 8.0;
  return g;
}

namespace {

// The baseline's tracker, one that declares whole-domain reach-avoid (TrackerCapabilities): the
// first agent's, with the parameters the problem gives it, else the first installed one's, with
// its defaults; none when no tracker declares it.
std::optional<PluginChoice> baseline_tracker(const Problem& pb, TrackerInstances& instances) {
  const auto declares = [&](const PluginChoice& choice) {
    try {
      return instances.get(choice)->capabilities().reach_avoid;
    } catch (const std::exception&) {  // not installed, or bad parameters: not this one
      return false;
    }
  };
  for (const auto& a : pb.agents)
    if (declares(a.tracker)) return a.tracker;
  for (const auto& name : instances.registry().names(PluginKind<Tracker>::name))
    if (declares({name, {}})) return PluginChoice{name, {}};
  return std::nullopt;
}

}  // namespace

GlobalAbcdEstimate attempt_global_abcd(const Problem& pb, TrackerInstances& instances, const SolveOptions& opt,
                                       const std::function<void(const std::string&)>& log) {
  GlobalAbcdEstimate est = estimate_global_abcd(pb);
  const std::optional<PluginChoice> tracker = est.status.empty() ? baseline_tracker(pb, instances) : std::nullopt;
  if (!est.status.empty()) {
    // estimate_global_abcd said why not
  } else if (!tracker) {
    est.status = "skipped: no installed tracker declares whole-domain reach-avoid";
  } else if (est.memory_bytes_estimate > opt.global_memory_budget_bytes) {
    est.status = opt.global_memory_budget_bytes <= 0 ? "skipped: disabled (--global-budget 0)"
                                                     : "skipped: the estimate exceeds the memory budget";
  } else if (pb.agents.size() < 2) {
    est.status = "skipped: a single agent has no product to abstract";
  } else if (!pb.formation.empty()) {
    est.status = "skipped: formation constraints are not supported by the global baseline";
  } else {
    log("[global] abstraction of the product system over its whole domain (" +
        std::to_string(est.state_input_pairs) + " state-input pairs)");
    // The baseline is a tracker's whole-domain mode, whatever tracks the agents.
    const GlobalAbcdRun g = run_global_abcd(pb, *instances.get(*tracker), opt.threads, opt.global_memory_budget_bytes);
    est.status = g.status;
    est.time_s = g.time_s;
    est.boxes_computed = g.boxes_computed;
    est.attempted = true;
    log("[global] " + g.status + " in " + number_text(g.time_s, 3) + " s");
  }
  return est;
}

}  // namespace marsyn
