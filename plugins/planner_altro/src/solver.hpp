#pragma once
// The solver's internal state and steps (not part of the plugin's interface). One Solver lives
// for one solve() call, so Planner::solve stays const and thread-safe.
#include <algorithm>
#include <functional>
#include <iterator>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "altro_solver.hpp"
#include "marsyn/stopwatch.hpp"
#include "marsyn/planner_support/chunk_pool.hpp"
#include "marsyn/planner_support/proximity_screen.hpp"

namespace marsyn::altro::detail {

using Mat = Eigen::MatrixXd;
using Vec = Eigen::VectorXd;
// The row-major Jacobians rk4_jacobians_staged writes, read in place.
using RowMap = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;
constexpr double kInf = std::numeric_limits<double>::infinity();

struct AgentBlock {
  const Dynamics* dyn;
  int xo, uo, n, m, group;
  unsigned reads = ~0u;  // the state coordinates the field reads (rk4_jacobians_staged)
};

struct Group {
  int xo, uo, n, m;
  int first, last;  // agents [first, last)
};

// One generic constraint's rows at one step: multipliers live in a flat array.
struct ConstraintRef {
  const Constraint* c;
  int rows, lam_offset;  // offset into a step's multiplier block
  std::vector<int> group_of, local;  // per support entry: group and index inside the group
  int groups_touched;
};

// The constraints of a list that can add anything at a point, in list order: the screen's near
// ones (ProximityScreen::near) and those holding a multiplier at the step (held: Solver::hold()).
// A satisfied row with a zero multiplier adds nothing to the cost, the expansion, the violation
// or the update, so visiting these alone gives the same sums as visiting the whole list.
inline void needed(const std::vector<int>& near, const std::vector<int>& held, std::vector<int>& out) {
  out.clear();
  std::set_union(near.begin(), near.end(), held.begin(), held.end(), std::back_inserter(out));
}

// PHR augmented-Lagrangian term for c <= 0: (max(0, lam + rho c)^2 - lam^2) / (2 rho).
inline double phr(double c, double lam, double rho) {
  const double s = std::max(0.0, lam + rho * c);
  return (s * s - lam * lam) / (2.0 * rho);
}

class Solver {
 public:
  Solver(const PlanningProblem& pp, const PlanOptions& run, const Options& opt)
      : pp_(pp), run_(run), opt_(opt), prob_(*pp.problem), T_(pp.horizon) {}

  PlanResult run();

 private:
  // Setup
  void prepare();  // the layout, the multipliers and scratch, the initial guess
  void layout();
  void initial_guess();
  // ref_: straight lines from x0 to the goal centre, bent sideways by `bend` x path length.
  void reference(double bend);
  // How deep ref_ cuts into the pair requirements: the sum of their squared positive rows.
  double reference_conflict() const;
  struct AgentGradient {
    int agent;
    Vec cx, cu;
  };
  // What one evaluation writes, one per thread (the solver's phases over knots or agents run on
  // several threads; everything else they read is fixed during the phase).
  struct Scratch {
    std::vector<double> g = std::vector<double>(64);
    std::vector<int> near, cand;  // ProximityScreen::near's list, needed()'s
    Vec z, dx, Kdx;  // (dx, Kdx: the forward pass's feedback term)
    planner_support::ProximityScreen::Buffers screen;
    std::vector<double> jac;
    std::vector<AgentGradient> grads;
    // Partial-step Jacobians of the current iterate at one (k, j), per agent, filled on demand:
    // row-major A (n x n) followed by B (n x m), in mid_jac_ or in own (when computed here).
    std::vector<const double*> AB;
    std::vector<std::vector<double>> own;
    std::vector<char> have_jac;
  };
  // Evaluation
  void rollout_nominal();
  // Z, where given: the interior points of every period of (X, U) as its rollout left them
  // (Z_ for X_, Zn_ for Xn_); null: integrated again.
  double stage_cost(int k, const Vec& x, const Vec* u, Scratch& s, const Vec* z = nullptr) const;
  double total_cost(const std::vector<Vec>& X, const std::vector<Vec>& U,
                    const std::vector<Vec>* Z = nullptr) const;
  double max_violation(const std::vector<Vec>& X, const std::vector<Vec>& U, std::string* worst,
                       const std::vector<Vec>* Z = nullptr) const;
  void update_multipliers();
  // held_c_, held_b_ from the multipliers as they now stand.
  void hold();
  // Between the samples (PlanningProblem::between, solver_between.cpp): rows at the interior
  // points of each period, functions of (x_k, u_k) through the partial RK4 step.
  // Z: the interior points of the period from x under u, point-major (points_ x n_).
  void interior_points(const Vec& x, const Vec& u, Vec& Z) const;
  // Period k's interior points of (X, U): (*Z)[k] when the rollout kept them, else into tmp.
  const Vec& points_at(int k, const std::vector<Vec>& X, const std::vector<Vec>& U, const std::vector<Vec>* Z,
                       Vec& tmp) const;
  double between_cost(int k, const Vec& x, const Vec& u, Scratch& s, const Vec* z) const;
  void for_each_between_row(const std::vector<Vec>& X, const std::vector<Vec>& U, const std::vector<Vec>* Z,
                            const std::function<void(int k, int j, const ConstraintRef& r, const double* g)>& f) const;
  double between_violation(const std::vector<Vec>& X, const std::vector<Vec>& U, const std::vector<Vec>* Z,
                           std::string* worst, double v) const;
  void update_between_multipliers();
  void expand_between(int k, Scratch& s);
  // Row i of a between row's gradient in (x_k, u_k), per agent it reads: dg/dz times the
  // partial step's Jacobians. Used by the expansion and the final projection.
  void between_gradients(int k, int j, const ConstraintRef& r, const double* jac, int row,
                         std::vector<AgentGradient>& out, Scratch& s) const;
  // Final projection: Gauss-Newton steps on the inputs onto the active constraints (polish.cpp).
  bool polish(double& viol, std::string& worst, const Stopwatch& clock);
  // A near-active row c at step k: its gradient in the product state at k (or, `input`, in u_k),
  // and a between row's direct gradient in u_k.
  struct PolishRow {
    int k;
    double c;
    std::vector<std::pair<int, double>> grad;  // product state (or input) index, dc/d
    bool input;
    std::vector<std::pair<int, double>> ugrad = {};  // a between row's direct dc/du_k
  };
  void between_polish_rows(double active, std::vector<PolishRow>& rows);
  void bound_polish_rows(double active, std::vector<PolishRow>& rows);
  bool polish_direction(const std::vector<PolishRow>& rows, Vec& dU) const;
  bool polish_line_search(const Vec& dU, double& viol, std::string& worst);
  // iLQR
  // One outer round's iLQR iterations at tolerance tol (regularization reg carried between
  // rounds); stops on a small decrease, the time limit (timed_out) or no descent (stalled).
  void inner_iterations(const Stopwatch& clock, double tol, double& reg, bool& timed_out, bool& stalled);
  PlanResult result(double viol, const std::string& worst, int outer, bool timed_out, bool polished,
                    const Stopwatch& clock) const;
  void linearize();
  void expand_costs();
  void expand_knot(int k, Scratch& s);
  bool backward(double reg, double& dv1, double& dv2);
  bool backward_group(int group, double reg, double& dv1, double& dv2);
  bool forward(double dv1, double dv2, double& alpha);
  // One period of agent a from x under u into out; with z and kept_points_, the period's
  // interior points (its own substep states) into z, point-major as interior_points writes them.
  void step_agent(const AgentBlock& a, const Vec& x, const Vec& u, Vec& out, Vec* z = nullptr) const;
  // The rollout's kept interior points, or null when they are not kept.
  const std::vector<Vec>* kept(const std::vector<Vec>& Z) const { return kept_points_ ? &Z : nullptr; }

  const PlanningProblem& pp_;
  const PlanOptions& run_;
  const Options& opt_;
  const Problem& prob_;
  const int T_;
  int n_ = 0, m_ = 0;
  std::vector<AgentBlock> agents_;
  std::vector<Group> groups_;
  std::vector<int> xgroup_, xlocal_;  // product state index -> group, index in group
  std::vector<ConstraintRef> stage_, terminal_, between_;
  int stage_rows_ = 0, terminal_rows_ = 0, between_rows_ = 0;
  // Broad phase over the pair rows of stage_ and between_: which may be near at a point.
  std::unique_ptr<planner_support::ProximityScreen> screen_, screen_b_;
  mutable std::vector<int> near_, cand_;  // the single-threaded callers' lists
  int points_ = 0;                     // interior points per period (0: samples only)
  std::vector<int> agent_of_;          // product state index -> agent
  std::vector<Vec> lam_b_;             // [k]: multipliers of the between rows, point-major
  // [k * G + group]: the between rows' blocks in u and (u, x), stored transposed (LuuT_ = Luu',
  // LuxT_ = Lux'): they are written and read by an agent's rows, which are then contiguous
  // columns instead of a few doubles of every column (the backward pass waited on those cache
  // lines, a tenth of its time on the drones).
  std::vector<Mat> LuuT_, LuxT_;
  // [k * G + group]: the agents whose rows of Luu, Lux hold this expansion's blocks (the
  // other rows are stale)
  std::vector<std::vector<int>> between_agents_;
  // The interior points are the periods' own RK4 substep states (solver_setup.cpp): every
  // rollout keeps them (Z_ with X_, Zn_ with Xn_, swapped with them) and the between rows read
  // them instead of integrating each period a second time, bit for bit the same numbers.
  bool kept_points_ = false;
  std::vector<Vec> Z_, Zn_;  // [k]: period k's interior points, point-major (points_ x n_)
  // One midpoint (points_ == 1, even substeps): linearize() keeps its partial-step Jacobians
  // (the sweep passes through it), bit for bit what between_gradients would compute.
  bool kept_mid_jacobians_ = false;
  // Of the iterate linearize() last saw, row-major, knot after knot (mid_stride_ doubles each), and
  // within a knot agent i's A (n x n) then B (n x m) from mid_at_[i]: written in place by the
  // Jacobian sweep (a thousand small heap matrices were a tenth of the continuous linearize's
  // cache misses).
  std::vector<double> mid_jac_;
  std::vector<long> mid_at_;
  long mid_stride_ = 0;

  std::vector<Vec> X_, U_, ref_;
  Vec goal_centre_;
  double bend_ = 0.0;  // the reference's bend (Options::bend, or larger from the bend search)
  bool uniform_q_ = true;  // q_stage_ is q_track everywhere (the cost then keeps its old arithmetic)
  Vec q_stage_;  // stage tracking weight per product coordinate: q_track x q_state
  // Multipliers: state bounds (lo, hi), input bounds, generic constraints, goal (terminal).
  std::vector<Vec> lam_xlo_, lam_xhi_, lam_ulo_, lam_uhi_, lam_c_;
  // The constraints holding a nonzero multiplier, in list order: stage_ at step k (held_c_[k]),
  // between_ at period k's point j (held_b_[k * points_ + j - 1]).
  std::vector<std::vector<int>> held_c_, held_b_;
  Vec lam_glo_, lam_ghi_, lam_t_;
  double rho_ = 1.0;
  // Per step: agent Jacobians; per step and group: cost expansion and gains.
  std::vector<Mat> A_, B_;           // [k * N + agent]
  std::vector<Mat> lxx_, K_;         // [k * G + group]
  std::vector<Vec> lx_, luu_, lu_, d_;
  std::vector<Vec> Xn_, Un_;         // forward-pass candidates
  int iterations_ = 0;
  double cost_ = kInf;
  mutable std::vector<double> scratch_ = std::vector<double>(64);
  int threads_ = 1;                  // Options::threads resolved
  std::unique_ptr<planner_support::ChunkPool> pool_;  // threads_ threads for this solve's loops
  mutable std::vector<Scratch> work_;  // [thread]
  mutable std::vector<double> knot_cost_;  // total_cost's per-knot terms, summed in knot order
  // Threads for a loop over `items` of `weight` agent-steps each: one for small work, where
  // waking the pool's threads would cost more than it saves.
  int threads_for(long items, long weight) const { return items * weight >= 256 ? threads_ : 1; }
};

}  // namespace marsyn::altro::detail
