#pragma once
// The synthesized controller as data, its versioned binary file, and the O(1) lookup.
//
// File layout (little-endian, docs/tracker.md): 8-byte magic "MARSYNCT", u32 format version,
// u64 payload size, payload, u64 FNV-1a hash of the payload. The payload holds the dynamics type,
// agent, dimensions, grid origin and eta_x, eps, W, tau, the input grid, and per step the tube's
// index box followed (for steps with inputs) by one u16 input index per tube cell, then (version
// 2) the period enclosures: u32 count, each u32 step, f64 t0, t1, state lo[n], hi[n], workspace
// lo[2], hi[2]; (version 3) one u8 per state coordinate, 1 where the dynamics is periodic in it
// (an angle the controller reads on any branch, docs/problem-format.md "Periodic coordinates").
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "input_grid.hpp"
#include "marsyn/tracker.hpp"
#include "uniform_grid.hpp"

namespace marsyn::abcd {

inline constexpr std::uint16_t kLosing = 0xFFFF;  // cell not in the winning set
inline constexpr std::uint16_t kTarget = 0xFFFE;  // whole-domain mode: target reached, no input needed
inline constexpr std::uint32_t kFormatVersion = 3;  // 2: period enclosures; 3: periodic coordinates

struct ControllerData {
  std::string dynamics_type, agent;
  int n = 0, m = 0;
  bool time_invariant = false;  // whole-domain mode: one table, used at every k
  double tau = 0.0;
  std::vector<double> origin, eta_x, eps, w;
  std::vector<double> u_lo, u_hi, eta_u;
  // Tracking: boxes for steps 0..T, inputs for steps 0..T-1 (step T needs no input).
  // Whole-domain: one box and one table.
  std::vector<IndexBox> boxes;
  std::vector<std::int64_t> offsets;  // start of each table in `inputs`
  std::vector<std::uint16_t> inputs;
  // Continuous time: sound enclosures of the closed loop between samples (tracking only).
  std::vector<PeriodEnclosure> enclosures;
  // Per state coordinate, 1 where the dynamics is periodic (Dynamics::periodic): a tracking
  // controller reads such an angle on the branch nearest its step's reference (lift_angle).
  // Empty (a version 2 file): none.
  std::vector<std::uint8_t> periodic;

  bool is_periodic(int i) const { return !time_invariant && i < static_cast<int>(periodic.size()) && periodic[static_cast<std::size_t>(i)]; }
  int tables() const { return static_cast<int>(offsets.size()); }
};

class GridController : public marsyn::Controller {
 public:
  explicit GridController(ControllerData d);
  int state_dim() const override { return data_.n; }
  int input_dim() const override { return data_.m; }
  int horizon() const override { return data_.time_invariant ? -1 : static_cast<int>(data_.boxes.size()) - 1; }
  // Ok: x's cell is winning at k and u is its stored input. OutsideHorizon: k beyond the tables
  // (tracking: k >= T, the spec is already met at T), or the whole-domain target is reached.
  ControlStatus input(const double* x, int k, double* u) const override;
  void write(const std::string& path) const override;
  const std::vector<PeriodEnclosure>& period_enclosures() const override { return data_.enclosures; }
  // C99 or SCOTS v0.2 (export_c.cpp, export_scs.cpp, docs/deploy.md).
  ExportResult export_to(const ExportRequest& request) const override;

  // Is x's cell winning at step k (step T: in the tube)?
  bool winning(const double* x, int k) const;
  // The cells that meet the box [lo, hi] at step k and are not winning (a cell outside the step's
  // table counts as not winning). The quantizer is monotone, so the cells a double of [lo, hi]
  // can fall in are exactly the index range [index(lo), index(hi)] per coordinate.
  std::int64_t losing_in_box(const double* lo, const double* hi, int k) const;
  const ControllerData& data() const { return data_; }
  const UniformGrid& grid() const { return grid_; }
  const InputGrid& input_grid() const { return ugrid_; }

 private:
  // Index of x's cell in table k, or -1 outside the step's box (periodic coordinates lifted first).
  std::int64_t locate(const double* x, int k) const;
 public:
  // The step's reference for reading an angle (the centre of the step's tube box, periodic
  // coordinates only; 0 elsewhere): what <prefix>_input lifts a measured angle to.
  double reference(int k, int i) const { return reference_[static_cast<std::size_t>(k) * static_cast<std::size_t>(data_.n) + static_cast<std::size_t>(i)]; }
  bool any_periodic() const { return !reference_.empty(); }

 private:
  std::vector<double> reference_;  // boxes x n, empty without periodic coordinates

  ControllerData data_;
  UniformGrid grid_;
  InputGrid ugrid_;
  // ugrid_.value(j) for every j, row j at j * m, when it has at most kInputTableMax doubles.
  static constexpr std::int64_t kInputTableMax = 1 << 16;
  std::vector<double> input_table_;
};

std::string serialize(const ControllerData& d);
ControllerData deserialize(const std::string& bytes, const std::string& what);
void write_controller(const ControllerData& d, const std::string& path);
// Throws std::runtime_error naming the file and the defect on a corrupt, truncated or
// mismatched file.
std::shared_ptr<const GridController> read_controller(const std::string& path);

}  // namespace marsyn::abcd
