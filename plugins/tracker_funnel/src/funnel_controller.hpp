#pragma once
// The funnel controller as data, its file, and its O(n m) evaluation:
//   u = sat_U(u_k + K_k (x - x_k))   for x in the verified set V_k of step k.
// V_0 is the initial box; V_k (k >= 1) is a parallelotope {x in box_k : |fl(S_k (x - c_k))|_inf
// <= 1} or a zonotope (membership.hpp), exactly the set the evaluation below accepts, floating
// point included (docs/soundness.md section 11). O(n^2) per call for parallelotopes; for
// zonotopes O(n p) when the least-norm coefficients lie in the cube, else one small simplex
// (n rows, p columns).
//
// File layout (binary_file.hpp envelope, magic "MARSYNFT", format 1): payload = dynamics type,
// agent, u32 n, m, T, f64 tau, eps[n], w[n], u_lo[m], u_hi[m]; per step k = 0..T: x_k[n],
// box lo[n], hi[n], u8 kind (0 box, 1 parallelotope, 2 zonotope); kind 1: c_k[n], S_k[n n]
// row-major; kind 2: u32 p, c_k[n], G_k[n p] column-major, tol[n]; per step k < T: u_k[m],
// K_k[m n] row-major; u32 enclosure count, each u32 step, f64 t0, t1, state lo[n], hi[n],
// workspace lo[2], hi[2]. Format 2 appends u32 invariant_from (format 1 files read as T + 1);
// format 3 one u8 per state coordinate, 1 where the dynamics is periodic (an angle read on any
// branch: lifted onto the nominal x_k's, docs/problem-format.md "Periodic coordinates").
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "marsyn/disturbance.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn::funnel {

inline constexpr std::uint32_t kFormatVersion = 3;  // 3: periodic coordinates

// How V_k is tested beyond its box: nothing more (the initial box), |fl(S (x - c))|_inf <= 1 (a
// parallelotope), or a zonotope c + G xi: the membership solver's xi must leave a residual
// |fl(G xi - (x - c))| <= tol per coordinate.
enum SetKind : std::uint8_t { kBox = 0, kParallelotope = 1, kZonotope = 2 };

struct StepSet {
  std::vector<double> lo, hi;  // box_k, inside the eps-box of x_k
  std::uint8_t kind = kBox;
  std::vector<double> c;       // n, unless kind == kBox
  std::vector<double> S;       // parallelotope: n x n row-major; zonotope: G, n x generators column-major
  int generators = 0;          // zonotope only
  std::vector<double> tol;     // zonotope only, n
};

struct FunnelData {
  std::string dynamics_type, agent;
  int n = 0, m = 0;
  double tau = 0.0;
  std::vector<double> eps, w, u_lo, u_hi;  // w: W's largest value (TubeParams::w)
  // W(x, u) as the synthesis reads it (not stored: a controller read back has W = w).
  DisturbanceBound dist;
  std::vector<std::vector<double>> x_nom;  // T + 1
  std::vector<std::vector<double>> u_nom;  // T
  std::vector<std::vector<double>> K;      // T, m x n row-major
  std::vector<StepSet> sets;               // T + 1
  std::vector<PeriodEnclosure> enclosures;
  // From this step on, each V_k is invariant: every state it accepts has the guarantee from there
  // (invariant_sets.hpp); before it, V_k only contains what the initial set reaches. T + 1: none.
  int invariant_from = 0;
  // Per state coordinate, 1 where the dynamics is periodic; empty: none.
  std::vector<std::uint8_t> periodic;

  int horizon() const { return static_cast<int>(u_nom.size()); }
};

class FunnelController : public marsyn::Controller {
 public:
  explicit FunnelController(FunnelData d);
  int state_dim() const override { return data_.n; }
  int input_dim() const override { return data_.m; }
  int horizon() const override { return data_.horizon(); }
  // Ok for x in V_k, k < T; OutsideDomain outside V_k; OutsideHorizon for k outside [0, T) (at T
  // the specification is met and no input is needed).
  ControlStatus input(const double* x, int k, double* u) const override;
  void write(const std::string& path) const override;
  const std::vector<PeriodEnclosure>& period_enclosures() const override { return data_.enclosures; }
  // C99 with the monitor in_set as <prefix>_inside (export_c.cpp, docs/deploy.md); SCOTS' format
  // is refused with the reason.
  ExportResult export_to(const ExportRequest& request) const override;

  // x in V_k (k = 0..T), periodic coordinates read on any branch (lifted onto x_k's).
  bool in_set(const double* x, int k) const;
  const FunnelData& data() const { return data_; }
  // Per step: the zonotope's least-norm map (membership.hpp), or empty.
  const std::vector<double>& least_norm(int k) const { return least_norm_[static_cast<std::size_t>(k)]; }

 private:
  // x with its periodic coordinates on the nominal's branch (in buf), or x itself.
  const double* lifted(const double* x, int k, double* buf) const;
  bool in_lifted_set(const double* x, int k) const;
  FunnelData data_;
  std::vector<std::vector<double>> least_norm_;
};

// The controller's memory as the allocator holds it: every object with each vector's block
// (glibc: the request plus an 8-byte header, rounded up to 16, at least 32). What a finished agent
// keeps until the run ends.
double heap_bytes(const FunnelController& c);
// The same before synthesis, an upper estimate at `horizon` steps: `parts` period enclosures per
// step (their workspace boxes at most max(n, 3) wide), every set a zonotope of `set_generators`
// generators with its least-norm map (a parallelotope, n generators, holds less).
double kept_bytes_bound(int n, int m, int horizon, int parts, int set_generators);

std::string serialize(const FunnelData& d);
FunnelData deserialize(const std::string& bytes, const std::string& what);
// Throws std::runtime_error naming the file and the defect.
std::shared_ptr<const FunnelController> read_controller(const std::string& path);

}  // namespace marsyn::funnel
