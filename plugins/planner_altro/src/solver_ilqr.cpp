// One iLQR iteration: linearization, cost expansion, block-wise backward pass, line search;
// and the outer augmented-Lagrangian loop around it.
#include "solver.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include "marsyn/number_text.hpp"
#include "rk4.hpp"

namespace marsyn::altro::detail {

void Solver::linearize() {
  const int N = static_cast<int>(agents_.size());
  pool_->run(T_, threads_for(T_, N), [&](int, int begin, int end) {
    for (int k = begin; k < end; ++k)
      for (int i = 0; i < N; ++i) {
        const auto& a = agents_[i];
        Mat& A = A_[k * N + i];
        Mat& B = B_[k * N + i];
        // rk4_jacobians writes row-major; Eigen's default is column-major.
        double Ar[kMaxDual * kMaxDual], Br[kMaxDual * kMaxDual];
        double* Am = kept_mid_jacobians_ ? mid_jac_.data() + k * mid_stride_ + mid_at_[i] : nullptr;
        rk4_jacobians_staged(*a.dyn, X_[k].data() + a.xo, U_[k].data() + a.uo, prob_.tau, prob_.rk4_substeps,
                             Ar, Br, a.reads, Am, Am ? Am + a.n * a.n : nullptr, prob_.rk4_substeps / 2);
        A = RowMap(Ar, a.n, a.n);
        B = RowMap(Br, a.n, a.m);
      }
  });
}

void Solver::expand_costs() {
  // Knots on several threads: knot k writes only its own blocks of the expansion.
  pool_->run(T_ + 1, threads_for(T_ + 1, static_cast<long>(agents_.size())), [&](int t, int begin, int end) {
    for (int k = begin; k < end; ++k) expand_knot(k, work_[t]);
  });
}

void Solver::expand_knot(int k, Scratch& s) {
  const int G = static_cast<int>(groups_.size());
  std::vector<double>& g = s.g;
  std::vector<double>& jac = s.jac;
  {
    const bool term = k == T_;
    const Vec& target = term ? goal_centre_ : ref_[k];
    const Vec& x = X_[k];
    for (int gi = 0; gi < G; ++gi) {
      const auto& gr = groups_[gi];
      Mat& lxx = lxx_[k * G + gi];
      Vec& lx = lx_[k * G + gi];
      lxx.setZero(gr.n, gr.n);
      if (term) lxx.diagonal().setConstant(opt_.q_terminal);
      else lxx.diagonal() = q_stage_.segment(gr.xo, gr.n);
      lx = lxx.diagonal().cwiseProduct(x.segment(gr.xo, gr.n) - target.segment(gr.xo, gr.n));
      if (!term) {
        Vec& luu = luu_[k * G + gi];
        Vec& lu = lu_[k * G + gi];
        luu.setConstant(gr.m, opt_.r_input);
        lu = opt_.r_input * U_[k].segment(gr.uo, gr.m);
        for (int j = 0; j < gr.m; ++j) {
          const int pj = gr.uo + j;
          const double slo = lam_ulo_[k][pj] + rho_ * (pp_.input_bounds.lo[pj] - U_[k][pj]);
          const double shi = lam_uhi_[k][pj] + rho_ * (U_[k][pj] - pp_.input_bounds.hi[pj]);
          if (slo > 0) lu[j] -= slo, luu[j] += rho_;
          if (shi > 0) lu[j] += shi, luu[j] += rho_;
        }
      }
      if (k == 0) continue;
      for (int i = 0; i < gr.n; ++i) {
        const int pi = gr.xo + i;
        const double lo = term ? pp_.goal.lo[pi] : -kInf, hi = term ? pp_.goal.hi[pi] : kInf;
        const double slo = std::isfinite(pp_.state_bounds.lo[pi])
                               ? lam_xlo_[k][pi] + rho_ * (pp_.state_bounds.lo[pi] - x[pi]) : 0.0;
        const double shi = std::isfinite(pp_.state_bounds.hi[pi])
                               ? lam_xhi_[k][pi] + rho_ * (x[pi] - pp_.state_bounds.hi[pi]) : 0.0;
        if (slo > 0) lx[i] -= slo, lxx(i, i) += rho_;
        if (shi > 0) lx[i] += shi, lxx(i, i) += rho_;
        if (term) {
          const double glo = std::isfinite(lo) ? lam_glo_[pi] + rho_ * (lo - x[pi]) : 0.0;
          const double ghi = std::isfinite(hi) ? lam_ghi_[pi] + rho_ * (x[pi] - hi) : 0.0;
          if (glo > 0) lx[i] -= glo, lxx(i, i) += rho_;
          if (ghi > 0) lx[i] += ghi, lxx(i, i) += rho_;
        }
      }
    }
    if (points_ > 0 && !term) expand_between(k, s);
    if (k == 0) return;
    auto add = [&](const ConstraintRef& r, const double* lam) {
      g.resize(std::max<size_t>(g.size(), r.rows));
      r.c->evaluate(x.data(), g.data(), nullptr);
      bool any = false;
      for (int j = 0; j < r.rows; ++j) any |= lam[r.lam_offset + j] + rho_ * g[j] > 0;
      if (!any) return;
      const int s = static_cast<int>(r.local.size());
      jac.resize(static_cast<size_t>(r.rows) * s);
      r.c->evaluate(x.data(), g.data(), jac.data());
      // Dropping cross-group blocks of rho J'J and scaling the kept ones by the number of groups
      // touched keeps the model an upper bound (Cauchy-Schwarz): a majorizer, so steps stay safe.
      const double scale = rho_ * r.groups_touched;
      for (int j = 0; j < r.rows; ++j) {
        const double mu = lam[r.lam_offset + j] + rho_ * g[j];
        if (mu <= 0) continue;
        const double* J = jac.data() + static_cast<size_t>(j) * s;
        for (int a = 0; a < s; ++a) {
          const int ga = r.group_of[a];
          lx_[k * G + ga][r.local[a]] += mu * J[a];
          Mat& lxx = lxx_[k * G + ga];
          for (int b = 0; b < s; ++b)
            if (r.group_of[b] == ga) lxx(r.local[a], r.local[b]) += scale * J[a] * J[b];
        }
      }
    };
    screen_->near(x.data(), s.near, s.screen);
    needed(s.near, held_c_[k], s.cand);
    for (int c : s.cand)
      if (applies_at(*stage_[c].c, k, T_)) add(stage_[c], lam_c_[k].data());
    if (term)
      for (const auto& r : terminal_) add(r, lam_t_.data());
  }
}

namespace {

// Q's rows [r, r + m) += the columns [r, r + m) of LT (a block stored transposed), element by
// element. Plain loops: as an Eigen expression of two storage orders in backward_group it
// changed GCC's inlining of that function's products (45-70 M more instructions on the drones).
void add_rows(const Mat& LT, int r, int m, Mat& Q) {
  for (int i = r; i < r + m; ++i)
    for (int c = 0; c < Q.cols(); ++c) Q(i, c) += LT(c, i);
}

}  // namespace

bool Solver::backward(double reg, double& dv1, double& dv2) {
  const int G = static_cast<int>(groups_.size());
  // Groups share nothing in the backward pass: several threads, each group's expected decrease
  // kept apart and summed in group order (the same sums for any number of threads).
  std::vector<double> e1(G, 0.0), e2(G, 0.0);
  std::vector<char> ok(G, 1);
  pool_->run(G, G > 1 ? threads_for(G, T_) : 1, [&](int, int begin, int end) {
    for (int gi = begin; gi < end; ++gi) ok[gi] = backward_group(gi, reg, e1[gi], e2[gi]);
  });
  dv1 = dv2 = 0.0;
  for (int gi = 0; gi < G; ++gi) {
    if (!ok[gi]) return false;
    dv1 += e1[gi];
    dv2 += e2[gi];
  }
  return true;
}

bool Solver::backward_group(int gi, double reg, double& dv1, double& dv2) {
  const int G = static_cast<int>(groups_.size());
  const int N = static_cast<int>(agents_.size());
  {
    const auto& gr = groups_[gi];
    Mat P = lxx_[T_ * G + gi];
    Vec p = lx_[T_ * G + gi];
    Mat PA(gr.n, gr.n), PB(gr.n, gr.m), Qxx, Qux(gr.m, gr.n), Quu(gr.m, gr.m), Pt(gr.n, gr.n);
    Vec Qx, Qu(gr.m), Quu_d(gr.m);
    // One factorization's storage for the whole horizon (compute() reuses it: no allocation per
    // knot; the same arithmetic as a fresh LLT).
    Eigen::LLT<Mat> llt(gr.m);
    for (int k = T_ - 1; k >= 0; --k) {
      // A and B are block diagonal over the group's agents: multiply block by block (lazy,
      // coefficient-wise products: the blocks are too thin for Eigen's blocked GEMM to pay off).
      for (int i = gr.first; i < gr.last; ++i) {
        const auto& a = agents_[i];
        const int lo = a.xo - gr.xo, lu = a.uo - gr.uo;
        PA.middleCols(lo, a.n).noalias() = P.middleCols(lo, a.n).lazyProduct(A_[k * N + i]);
        PB.middleCols(lu, a.m).noalias() = P.middleCols(lo, a.n).lazyProduct(B_[k * N + i]);
      }
      Qxx = lxx_[k * G + gi];
      Qx = lx_[k * G + gi];
      Quu.setZero();
      Quu.diagonal() = luu_[k * G + gi].array() + reg;
      Qu = lu_[k * G + gi];
      for (int i = gr.first; i < gr.last; ++i) {
        const auto& a = agents_[i];
        const int lo = a.xo - gr.xo, lu = a.uo - gr.uo;
        const Mat& Ak = A_[k * N + i];
        const Mat& Bk = B_[k * N + i];
        Qxx.middleRows(lo, a.n).noalias() += Ak.transpose().lazyProduct(PA.middleRows(lo, a.n));
        Quu.middleRows(lu, a.m).noalias() += Bk.transpose().lazyProduct(PB.middleRows(lo, a.n));
        Qux.middleRows(lu, a.m).noalias() = Bk.transpose().lazyProduct(PA.middleRows(lo, a.n));
        Qx.segment(lo, a.n).noalias() += Ak.transpose() * p.segment(lo, a.n);
        Qu.segment(lu, a.m).noalias() += Bk.transpose() * p.segment(lo, a.n);
      }
      if (points_ > 0)
        for (int i : between_agents_[k * G + gi]) {
          const int lu = agents_[i].uo - gr.uo, m = agents_[i].m;
          add_rows(LuuT_[k * G + gi], lu, m, Quu);
          add_rows(LuxT_[k * G + gi], lu, m, Qux);
        }
      llt.compute(Quu);
      if (llt.info() != Eigen::Success) return false;
      Mat& K = K_[k * G + gi];
      Vec& d = d_[k * G + gi];
      K = llt.solve(Qux);
      K = -K;
      d = llt.solve(Qu);
      d = -d;
      dv1 += d.dot(Qu);
      Quu_d.noalias() = Quu * d;
      dv2 += 0.5 * d.dot(Quu_d);
      // With K = -Quu^-1 Qux the usual update collapses to these two lines.
      P = Qxx;
      P.noalias() += Qux.transpose() * K;
      Pt = P.transpose();
      P = 0.5 * (P + Pt);
      p = Qx;
      p.noalias() += Qux.transpose() * d;
      if (!P.allFinite()) return false;
    }
  }
  return true;
}

bool Solver::forward(double dv1, double dv2, double& alpha) {
  const int G = static_cast<int>(groups_.size());
  alpha = 1.0;
  for (int ls = 0; ls < opt_.line_search_steps; ++ls, alpha *= 0.5) {
    Xn_[0] = X_[0];
    // Each group's rollout reads only its own states and gains: groups on several threads, each
    // writing its own segments of Xn_ and Un_.
    std::vector<char> finite_from(G, 1);
    pool_->run(G, G > 1 ? threads_for(G, T_) : 1, [&](int t, int begin, int end) {
      Vec& dx = work_[t].dx;
      Vec& Kdx = work_[t].Kdx;
      for (int gi = begin; gi < end; ++gi) {
        const auto& gr = groups_[gi];
        for (int k = 0; k < T_; ++k) {
          // The expression's own temporaries, kept per thread (the same product and sum).
          dx = Xn_[k].segment(gr.xo, gr.n) - X_[k].segment(gr.xo, gr.n);
          Kdx.noalias() = K_[k * G + gi] * dx;
          Un_[k].segment(gr.uo, gr.m) = U_[k].segment(gr.uo, gr.m) + alpha * d_[k * G + gi] + Kdx;
          for (int i = gr.first; i < gr.last; ++i)
            step_agent(agents_[i], Xn_[k], Un_[k], Xn_[k + 1], kept_points_ ? &Zn_[k] : nullptr);
          if (!Xn_[k + 1].segment(gr.xo, gr.n).allFinite()) {
            finite_from[gi] = 0;
            break;
          }
        }
      }
    });
    if (std::find(finite_from.begin(), finite_from.end(), 0) != finite_from.end()) continue;
    const double J = total_cost(Xn_, Un_, kept(Zn_));
    const double expected = -(alpha * dv1 + alpha * alpha * dv2);
    if (!std::isfinite(J)) continue;
    const double ratio = expected > 0 ? (cost_ - J) / expected : (J < cost_ ? 1.0 : -1.0);
    if (ratio > 1e-4 && ratio < 10.0 && J < cost_) {
      std::swap(X_, Xn_);
      std::swap(U_, Un_);
      std::swap(Z_, Zn_);
      cost_ = J;
      return true;
    }
  }
  return false;
}

void Solver::prepare() {
  layout();
  const int N = static_cast<int>(agents_.size()), G = static_cast<int>(groups_.size());
  lam_xlo_.assign(T_ + 1, Vec::Zero(n_));
  lam_xhi_ = lam_xlo_;
  lam_ulo_.assign(T_, Vec::Zero(m_));
  lam_uhi_ = lam_ulo_;
  lam_c_.assign(T_ + 1, Vec::Zero(stage_rows_));
  lam_glo_ = lam_ghi_ = Vec::Zero(n_);
  lam_t_ = Vec::Zero(terminal_rows_);
  A_.resize(static_cast<size_t>(T_) * N);
  B_.resize(A_.size());
  if (kept_mid_jacobians_) {
    mid_at_.assign(N, 0);
    mid_stride_ = 0;
    for (int i = 0; i < N; ++i) {
      mid_at_[i] = mid_stride_;
      mid_stride_ += static_cast<long>(agents_[i].n) * (agents_[i].n + agents_[i].m);
    }
    mid_jac_.assign(static_cast<size_t>(T_ * mid_stride_), 0.0);
  }
  lxx_.resize(static_cast<size_t>(T_ + 1) * G);
  lx_.resize(lxx_.size());
  luu_.resize(lxx_.size());
  lu_.resize(lxx_.size());
  K_.resize(lxx_.size());
  d_.resize(lxx_.size());
  if (points_ > 0) {
    lam_b_.assign(T_, Vec::Zero(static_cast<long>(points_) * between_rows_));
    LuuT_.resize(lxx_.size());
    LuxT_.resize(lxx_.size());
    between_agents_.assign(lxx_.size(), {});
  }
  hold();
  rho_ = opt_.penalty_initial;
  threads_ = planner_support::solver_threads(opt_.threads);
  pool_ = std::make_unique<planner_support::ChunkPool>(threads_);
  work_.assign(threads_, Scratch{});
  for (auto& w : work_) {
    w.AB.assign(N, nullptr);
    w.own.resize(N);
    w.have_jac.assign(N, 0);
  }
  initial_guess();
  Xn_ = X_;
  Un_ = U_;
  Zn_ = Z_;
  cost_ = total_cost(X_, U_, kept(Z_));
}

void Solver::inner_iterations(const Stopwatch& clock, double tol, double& reg, bool& timed_out, bool& stalled) {
  for (int inner = 0; inner < opt_.max_inner && iterations_ < opt_.max_iterations; ++inner) {
    if (clock.seconds() > run_.time_limit_s) {
      timed_out = true;
      break;
    }
    ++iterations_;
    linearize();
    expand_costs();
    double dv1, dv2, alpha = 0.0;
    bool ok = false;
    while (reg <= opt_.reg_max) {
      if (backward(reg, dv1, dv2)) {
        ok = true;
        break;
      }
      reg *= opt_.reg_factor;
    }
    if (!ok) {
      stalled = true;
      break;
    }
    const double before = cost_;
    if (!forward(dv1, dv2, alpha)) {
      reg = std::max(reg * opt_.reg_factor * opt_.reg_factor, 1e-6);
      if (reg > opt_.reg_max) {
        stalled = true;
        break;
      }
      continue;
    }
    // Small accepted steps mean the model is poor: raise regularization, as for a failure.
    if (alpha <= opt_.small_step) reg = std::min(reg * opt_.reg_factor, opt_.reg_max);
    else if (alpha == 1.0) reg = std::max(reg / opt_.reg_factor, opt_.reg_min);
    if (run_.progress) run_.progress({iterations_, cost_, -1.0});
    const double decrease = before - cost_;
    if (decrease < tol * std::max(1.0, std::abs(cost_))) break;
  }
}

PlanResult Solver::run() {
  const Stopwatch clock;
  prepare();
  double reg = opt_.reg_initial;
  std::string worst;
  double viol = max_violation(X_, U_, &worst, kept(Z_));
  bool timed_out = false, stalled = false, polished = false;
  double polish_below = opt_.polish_start;
  int outer = 0;
  for (; outer < opt_.max_outer; ++outer) {
    const double tol = viol <= 1e2 * opt_.constraint_tolerance ? opt_.cost_tolerance : opt_.cost_tolerance_intermediate;
    inner_iterations(clock, tol, reg, timed_out, stalled);
    viol = max_violation(X_, U_, &worst, kept(Z_));
    if (run_.progress) run_.progress({iterations_, cost_, viol});
    if (viol <= opt_.constraint_tolerance || timed_out || iterations_ >= opt_.max_iterations) break;
    // Close enough for the projection to finish: cheaper than more penalty rounds. An attempt
    // that does not finish leaves the iterate where the penalty rounds had it: its partial steps
    // ignore the cost, and continuing from them cost crane_vehicle a second solve. After a
    // failed attempt the next waits for a tenth of its violation.
    if (viol <= polish_below) {
      const std::vector<Vec> X = X_, U = U_, Z = Z_;
      const double v = viol;
      const std::string w = worst;
      if (polish(viol, worst, clock)) {
        polished = true;
        break;
      }
      X_ = X, U_ = U, Z_ = Z, viol = v, worst = w;
      polish_below = 0.1 * v;
    }
    if (stalled && rho_ >= opt_.penalty_max) break;
    stalled = false;
    update_multipliers();
    rho_ = std::min(rho_ * opt_.penalty_scaling, opt_.penalty_max);
    reg = std::max(reg, opt_.reg_initial);
    cost_ = total_cost(X_, U_, kept(Z_));
  }
  if (viol > opt_.constraint_tolerance && viol <= opt_.polish_max_violation && !timed_out)
    polished = polish(viol, worst, clock);
  cost_ = total_cost(X_, U_, kept(Z_));
  return result(viol, worst, outer, timed_out, polished, clock);
}

// The plan and how the run ended: converged, or why not (time, penalty at its maximum).
PlanResult Solver::result(double viol, const std::string& worst, int outer, bool timed_out, bool polished,
                          const Stopwatch& clock) const {
  PlanResult res;
  res.plan.tau = prob_.tau;
  res.plan.x = X_;
  res.plan.u = U_;
  res.iterations = iterations_;
  res.solve_time_s = clock.seconds();
  res.max_violation = viol;
  res.cost = cost_;
  std::ostringstream msg;
  msg.precision(kMessageDigits);
  if (viol <= opt_.constraint_tolerance) {
    res.status = PlannerStatus::ExactSolution;
    msg << "converged: violation " << viol << " after " << outer + 1 << " outer updates"
        << (polished ? " and the final projection" : "");
  } else {
    res.status = timed_out ? PlannerStatus::Timeout
                 : (rho_ >= opt_.penalty_max || outer >= opt_.max_outer) && viol > 1e-2 ? PlannerStatus::Infeasible
                                                                                        : PlannerStatus::ApproximateSolution;
    msg << (timed_out ? "time limit reached" : "no feasible plan found") << ": '" << worst << "' violated by "
        << viol << " after " << iterations_ << " iterations, penalty " << rho_
        << (res.status == PlannerStatus::Infeasible ? " (penalty at its maximum: likely infeasible at this horizon)"
                                                    : "");
  }
  if (bend_ != opt_.bend) msg << "; references bent " << bend_ / opt_.bend << "x further (they met at bend " << opt_.bend << ")";
  res.message = msg.str();
  return res;
}

}  // namespace marsyn::altro::detail
