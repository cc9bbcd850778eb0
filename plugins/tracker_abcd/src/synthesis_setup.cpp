#include "synthesis_setup.hpp"

#include <algorithm>
#include <cmath>

namespace marsyn::abcd {

std::vector<bool> invariant_coords(const Dynamics& f) {
  auto inv = f.field_independent_of();
  if (static_cast<int>(inv.size()) != f.state_dim()) inv.assign(static_cast<size_t>(f.state_dim()), false);
  return inv;
}

std::vector<double> to_std(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

std::string check_dynamics(const Dynamics* f) {
  if (!f) return "no dynamics";
  const int n = f->state_dim(), m = f->input_dim();
  if (n < 1 || n > kMaxDim || m < 1 || m > kMaxDim) return "unsupported dimensions";
  return {};
}

namespace {

std::string check_vector(const Eigen::VectorXd& v, int size, const char* name, bool positive) {
  if (v.size() != size) return std::string(name) + " has " + std::to_string(v.size()) + " entries, expected " + std::to_string(size);
  for (int i = 0; i < size; ++i) {
    if (!std::isfinite(v[i])) return std::string(name) + " is not finite";
    if (positive ? !(v[i] > 0) : !(v[i] >= 0)) return std::string(name) + (positive ? " must be positive" : " must be non-negative");
  }
  return {};
}

}  // namespace

std::string check_vectors(std::initializer_list<VectorCheck> checks) {
  for (const VectorCheck& c : checks) {
    std::string e = check_vector(*c.v, c.size, c.name, c.positive);
    if (!e.empty()) return e;
  }
  return {};
}

std::string make_grids(const Eigen::VectorXd& lo, const Eigen::VectorXd& eta_x, const Box& input_bounds,
                       const Eigen::VectorXd& eta_u, UniformGrid& g, InputGrid& ug) {
  try {
    g = UniformGrid(to_std(lo), to_std(eta_x));
    ug = InputGrid(to_std(input_bounds.lo), to_std(input_bounds.hi), to_std(eta_u));
  } catch (const std::exception& e) {
    return e.what();
  }
  if (ug.size() >= kTarget) return "more than 65533 grid inputs";
  return {};
}

ControllerData controller_header(const Dynamics& f, const std::string& agent, double tau, const UniformGrid& g,
                                 const InputGrid& ug, const Eigen::VectorXd& w) {
  ControllerData d;
  d.dynamics_type = f.type();
  for (bool p : f.periodic()) d.periodic.push_back(p ? 1 : 0);
  d.agent = agent;
  d.n = f.state_dim();
  d.m = f.input_dim();
  d.tau = tau;
  d.origin = g.origin();
  d.eta_x = g.eta();
  d.w = to_std(w);
  d.u_lo = ug.lo();
  d.u_hi = ug.hi();
  d.eta_u = ug.eta();
  return d;
}

void drop_unshiftable(const UniformGrid& g, const IndexBox& b, std::vector<bool>& inv) {
  for (int i = 0; i < b.n; ++i)
    if (inv[i] && (!SuccessorTable::shift_valid(g, i, b.lo[i] - 1000) || !SuccessorTable::shift_valid(g, i, b.hi[i] + 1000)))
      inv[i] = false;
}

std::vector<std::unique_ptr<SuccessorTable>> make_tables(int threads, const SuccessorBox& sb, const UniformGrid& g,
                                                         const InputGrid& ug, const std::vector<bool>& inv,
                                                         int prefilter_substeps) {
  std::vector<std::unique_ptr<SuccessorTable>> tables;
  for (int t = 0; t < threads; ++t) tables.push_back(std::make_unique<SuccessorTable>(sb, g, ug, inv, prefilter_substeps));
  return tables;
}

double sum_tables(const std::vector<std::unique_ptr<SuccessorTable>>& tables, long long& boxes_computed) {
  double seconds = 0;
  for (const auto& tab : tables) {
    boxes_computed += tab->computed();
    seconds += tab->seconds();
  }
  return seconds;
}

void record_times(double box_seconds, int threads, const Stopwatch& clock, TrackerStats& st) {
  st.abstraction_time_s = box_seconds / threads;
  st.synthesis_time_s = std::max(0.0, clock.seconds() - st.abstraction_time_s);
}

TrackResult invalid_input(std::string message) {
  TrackResult r;
  r.status = TrackerStatus::InvalidInput;
  r.message = std::move(message);
  return r;
}

void GridFigures::publish(TrackerStats& st) const {
  st.set("tube_cells", "tube cells", tube_cells);
  st.set("initial_state_winning", "x0's cell winning", initial_state_winning);
  st.set("winning_cells_per_step", "winning cells/step", winning_cells_per_step);
  // Winning sets are invariant by construction (docs/soundness.md section 6): from every step.
  st.set("invariant_from", "leading sets not invariant", 0LL);
}

}  // namespace marsyn::abcd
