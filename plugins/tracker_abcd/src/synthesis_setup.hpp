#pragma once
// What the tube sweep (synthesis.cpp) and the whole-domain fixed point (reach_avoid.cpp) share:
// their input checks, the grids, the controller's header fields and the per-thread successor
// tables.
#include <initializer_list>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "controller_file.hpp"
#include "marsyn/stopwatch.hpp"
#include "marsyn/tracker.hpp"
#include "successor_cache.hpp"

namespace marsyn::abcd {

std::vector<bool> invariant_coords(const Dynamics& f);
std::vector<double> to_std(const Eigen::VectorXd& v);

template <class Fn>
void run_threads(int threads, Fn fn) {
  if (threads <= 1) {
    fn(0);
    return;
  }
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(fn, t);
  for (auto& th : pool) th.join();
}

// "no dynamics" or "unsupported dimensions", else "".
std::string check_dynamics(const Dynamics* f);

struct VectorCheck {
  const Eigen::VectorXd* v;
  int size;
  const char* name;
  bool positive;  // else non-negative
};
// The first vector with the wrong size, a non-finite or an out-of-sign entry, else "".
std::string check_vectors(std::initializer_list<VectorCheck> checks);

// Builds the state grid (origin `lo`) and the input grid: "" or why they cannot be built.
std::string make_grids(const Eigen::VectorXd& lo, const Eigen::VectorXd& eta_x, const Box& input_bounds,
                       const Eigen::VectorXd& eta_u, UniformGrid& g, InputGrid& ug);

// The fields of a controller file both modes fill alike (the eps, tables and inputs are theirs).
ControllerData controller_header(const Dynamics& f, const std::string& agent, double tau, const UniformGrid& g,
                                 const InputGrid& ug, const Eigen::VectorXd& w);

// The whole-cell shift needs moderate indices (successor_cache.hpp); beyond them a coordinate
// simply is not reused.
void drop_unshiftable(const UniformGrid& g, const IndexBox& b, std::vector<bool>& inv);

std::vector<std::unique_ptr<SuccessorTable>> make_tables(int threads, const SuccessorBox& sb, const UniformGrid& g,
                                                         const InputGrid& ug, const std::vector<bool>& inv,
                                                         int prefilter_substeps);

// Adds the tables' computed boxes to `boxes_computed`; returns their seconds, summed.
double sum_tables(const std::vector<std::unique_ptr<SuccessorTable>>& tables, long long& boxes_computed);

// The sweep's times from the tables' seconds (summed over `threads` threads): the successor
// boxes' share of the wall clock as abstraction, the rest since `clock` started as synthesis.
void record_times(double box_seconds, int threads, const Stopwatch& clock, TrackerStats& st);

// A request refused before any work: TrackerStatus::InvalidInput with this message.
TrackResult invalid_input(std::string message);

// The figures abcd reports beyond every tracker's (TrackerStats::figures, docs/tracker.md
// "Statistics"): the grid's cells, counted as the tube is laid out and swept.
struct GridFigures {
  long long tube_cells = 0;                     // summed over the steps k = 0..T
  std::vector<long long> winning_cells_per_step;
  bool initial_state_winning = false;           // x_0's cell is winning at step 0
  void publish(TrackerStats& st) const;         // sets them in st.figures, by name
};

}  // namespace marsyn::abcd
