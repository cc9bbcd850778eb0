#include "nlopt_solver.hpp"

#include <algorithm>
#include <cmath>
#include <nlopt.hpp>
#include <sstream>

#include "marsyn/stopwatch.hpp"
#include "marsyn/planner_support/invalid_input.hpp"
#include "marsyn/planner_support/product_model.hpp"
#include "marsyn/number_text.hpp"

namespace marsyn::nlopt_planner {

namespace {

using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;

class Shooting {
 public:
  Shooting(const planner_support::ProductModel& model, const Options& o, const PlanOptions& run)
      : M_(model), o_(o), run_(run), T_(model.T), n_(model.n), m_(model.m), N_(model.T * model.m) {
    rows_ = T_ * M_.path.rows() + M_.terminal.rows() + T_ * M_.points * M_.between.rows();
    U_.assign(T_, Vec(m_));
    A_.resize(T_);
    B_.resize(T_);
  }
  int variables() const { return N_; }
  int rows() const { return rows_; }

  double objective(const double* z, double* grad) {
    load(z, grad != nullptr);
    const Vec e = X_[T_] - M_.goal_centre;
    double J = 0.5 * o_.q_terminal * e.squaredNorm();
    for (const auto& u : U_) J += 0.5 * o_.r_input * u.squaredNorm();
    if (grad) {
      // Adjoint: lam_k = dJ/dx_k through the rollout; only x_T carries cost.
      Vec lam = o_.q_terminal * e;
      for (int k = T_ - 1; k >= 0; --k) {
        const Vec g = o_.r_input * U_[k] + B_[k].transpose() * lam;
        for (int j = 0; j < m_; ++j) grad[k * m_ + j] = g[j];
        lam = A_[k].transpose() * lam;
      }
    }
    ++evaluations_;
    last_cost_ = J;
    return J;
  }

  void constraints(double* c, const double* z, double* grad) {
    load(z, grad != nullptr);
    const int pr = M_.path.rows(), tr = M_.terminal.rows();
    std::vector<double> jac(std::max({M_.path.nonzeros(), M_.terminal.nonzeros(), 1}));
    Mat Jp(pr, n_), Jt(tr, n_);
    // S = d x_k / d U (n x N), zero beyond the inputs already applied.
    Mat S = Mat::Zero(n_, grad ? N_ : 0);
    if (grad) std::fill(grad, grad + static_cast<size_t>(rows_) * N_, 0.0);
    const int br = M_.between.rows();
    std::vector<double> bjac(std::max(M_.between.nonzeros(), 1));
    Mat Jb(br, n_), Az, Bz;
    Vec zj(n_);
    for (int k = 1; k <= T_; ++k) {
      // The between rows of period k - 1 (S is still d x_{k-1} / dU here).
      for (int j = 1; j <= M_.points && br > 0; ++j) {
        const int r0 = T_ * pr + tr + ((k - 1) * M_.points + (j - 1)) * br;
        M_.interior(X_[k - 1].data(), U_[k - 1].data(), j, zj.data());
        M_.between.evaluate(zj.data(), c + r0, grad ? bjac.data() : nullptr);
        if (grad) {
          M_.between.dense(bjac.data(), Jb);
          M_.interior_jacobians(X_[k - 1].data(), U_[k - 1].data(), j, Az, Bz);
          Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> G(grad + static_cast<size_t>(r0) * N_, br, N_);
          const int used = (k - 1) * m_;
          if (used > 0) G.leftCols(used) = (Jb * Az) * S.leftCols(used);
          G.middleCols(used, m_) = Jb * Bz;
        }
      }
      if (grad) {
        const int used = (k - 1) * m_;
        if (used > 0) S.leftCols(used) = A_[k - 1] * S.leftCols(used);
        S.middleCols(used, m_) = B_[k - 1];
      }
      const int r0 = (k - 1) * pr;
      M_.path.evaluate(X_[k].data(), c + r0, grad ? jac.data() : nullptr, k);
      if (grad && pr > 0) {
        M_.path.dense(jac.data(), Jp);
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> G(grad + static_cast<size_t>(r0) * N_, pr, N_);
        G.leftCols(k * m_) = Jp * S.leftCols(k * m_);
      }
    }
    if (tr > 0) {
      const int r0 = T_ * pr;
      M_.terminal.evaluate(X_[T_].data(), c + r0, grad ? jac.data() : nullptr);
      if (grad) {
        M_.terminal.dense(jac.data(), Jt);
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> G(grad + static_cast<size_t>(r0) * N_, tr, N_);
        G = Jt * S;
      }
    }
    double v = 0.0;
    for (int r = 0; r < rows_; ++r) v = std::max(v, c[r]);
    last_violation_ = v;
    // AUGLAG returns its last subproblem's point, not the best feasible one it passed through.
    if (v <= o_.feasibility_tolerance) {
      const double J = cost_at_loaded();
      if (best_.empty() || J < best_cost_) {
        best_.assign(z, z + N_);
        best_cost_ = J;
      }
    }
    if (run_.progress && evaluations_ % 50 == 0) run_.progress({static_cast<int>(evaluations_), last_cost_, v});
  }

  const std::vector<double>& best() const { return best_; }
  long evaluations() const { return evaluations_; }

 private:
  double cost_at_loaded() const {
    double J = 0.5 * o_.q_terminal * (X_[T_] - M_.goal_centre).squaredNorm();
    for (const auto& u : U_) J += 0.5 * o_.r_input * u.squaredNorm();
    return J;
  }

  // NLopt asks for the objective and the constraints at the same point separately.
  void load(const double* z, bool derivatives) {
    const bool same = !z_.empty() && std::equal(z_.begin(), z_.end(), z);
    if (!same) {
      z_.assign(z, z + N_);
      for (int k = 0; k < T_; ++k)
        for (int j = 0; j < m_; ++j) U_[k][j] = z[k * m_ + j];
      X_ = M_.rollout(U_);
      have_jac_ = false;
    }
    if (derivatives && !have_jac_) {
      for (int k = 0; k < T_; ++k) M_.jacobians(X_[k].data(), U_[k].data(), A_[k], B_[k]);
      have_jac_ = true;
    }
  }

  const planner_support::ProductModel& M_;
  const Options& o_;
  const PlanOptions& run_;
  const int T_, n_, m_, N_;
  int rows_ = 0;
  std::vector<double> z_;
  std::vector<Vec> U_, X_;
  std::vector<Mat> A_, B_;
  bool have_jac_ = false;
  long evaluations_ = 0;
  double last_cost_ = 0.0, last_violation_ = 0.0;
  std::vector<double> best_;
  double best_cost_ = 0.0;
};

double objective_cb(unsigned, const double* z, double* grad, void* data) {
  return static_cast<Shooting*>(data)->objective(z, grad);
}
void constraints_cb(unsigned, double* c, unsigned, const double* z, double* grad, void* data) {
  static_cast<Shooting*>(data)->constraints(c, z, grad);
}

}  // namespace

// NLopt's successful returns in its manual's words (docs/messages.md: no raw codes); failures
// arrive as exceptions.
std::string result_words(nlopt::result r) {
  switch (r) {
    case nlopt::SUCCESS: return "success";
    case nlopt::STOPVAL_REACHED: return "the objective reached its stop value";
    case nlopt::FTOL_REACHED: return "the objective changed less than its tolerance";
    case nlopt::XTOL_REACHED: return "the inputs changed less than their tolerance";
    case nlopt::MAXEVAL_REACHED: return "the evaluation limit was reached";
    case nlopt::MAXTIME_REACHED: return "the time limit was reached";
    default: return "an outcome its manual does not list (" + std::to_string(static_cast<int>(r)) + ")";
  }
}

PlanResult solve(const PlanningProblem& pp, const PlanOptions& run, const Options& o) {
  const Stopwatch clock;
  if (auto refused = planner_support::invalid_input(pp)) return *refused;
  PlanResult res;
  planner_support::ProductModel model(pp);
  Shooting sh(model, o, run);
  if (static_cast<double>(sh.rows()) * sh.variables() > o.max_dense_entries) {
    res.status = PlannerStatus::InvalidInput;
    std::ostringstream os;
    os.precision(kMessageDigits);
    os << "single shooting needs a dense " << sh.rows() << " x " << sh.variables()
       << " constraint Jacobian, above max_dense_entries = " << o.max_dense_entries << "; use ipopt or altro";
    res.message = os.str();
    return res;
  }
  const int N = sh.variables();
  const bool auglag = o.algorithm.rfind("auglag", 0) == 0;
  const nlopt::algorithm outer = auglag                 ? nlopt::AUGLAG
                                 : o.algorithm == "mma" ? nlopt::LD_MMA
                                                        : nlopt::LD_SLSQP;
  nlopt::opt opt(outer, N);
  std::vector<double> lo(N), hi(N);
  for (int k = 0; k < model.T; ++k)
    for (int j = 0; j < model.m; ++j) {
      lo[k * model.m + j] = pp.input_bounds.lo[j];
      hi[k * model.m + j] = pp.input_bounds.hi[j];
    }
  opt.set_lower_bounds(lo);
  opt.set_upper_bounds(hi);
  opt.set_min_objective(objective_cb, &sh);
  opt.add_inequality_mconstraint(constraints_cb, &sh, std::vector<double>(sh.rows(), 0.1 * o.feasibility_tolerance));
  opt.set_xtol_rel(o.xtol_rel);
  opt.set_ftol_rel(o.ftol_rel);
  opt.set_maxeval(static_cast<int>(std::min<long>(o.max_evaluations, 1L << 30)));
  opt.set_maxtime(std::max(1e-3, run.time_limit_s));
  if (auglag) {
    nlopt::opt local(o.algorithm == "auglag_slsqp" ? nlopt::LD_SLSQP : nlopt::LD_LBFGS, N);
    local.set_xtol_rel(o.xtol_rel);
    local.set_ftol_rel(o.ftol_rel);
    local.set_maxeval(2000);
    opt.set_local_optimizer(local);
  }
  std::vector<double> z(N);
  const auto U0 = model.initial_inputs();
  for (int k = 0; k < model.T; ++k)
    for (int j = 0; j < model.m; ++j) z[k * model.m + j] = U0[k][j];
  double f = 0.0;
  std::string nlopt_note;
  try {
    const nlopt::result r = opt.optimize(z, f);
    nlopt_note = "NLopt: " + result_words(r);
  } catch (const nlopt::roundoff_limited&) {
    nlopt_note = "NLopt: roundoff limited the progress";
  } catch (const nlopt::forced_stop&) {
    nlopt_note = "NLopt: stopped on request";
  } catch (const std::exception& e) {
    nlopt_note = std::string("NLopt: ") + e.what();
  }
  if (!sh.best().empty()) z = sh.best();
  std::vector<Vec> U(model.T, Vec(model.m));
  for (int k = 0; k < model.T; ++k)
    for (int j = 0; j < model.m; ++j) U[k][j] = std::clamp(z[k * model.m + j], lo[k * model.m + j], hi[k * model.m + j]);
  res.plan.tau = model.tau;
  res.plan.x = model.rollout(U);
  res.plan.u = U;
  std::string worst;
  res.max_violation = model.violation(res.plan.x, U, &worst);
  res.cost = 0.5 * o.q_terminal * (res.plan.x.back() - model.goal_centre).squaredNorm();
  for (const auto& u : U) res.cost += 0.5 * o.r_input * u.squaredNorm();
  res.iterations = static_cast<int>(sh.evaluations());
  res.solve_time_s = clock.seconds();
  if (res.max_violation <= o.feasibility_tolerance) {
    res.status = PlannerStatus::ExactSolution;
  } else {
    res.status = res.solve_time_s >= run.time_limit_s ? PlannerStatus::Timeout : PlannerStatus::ApproximateSolution;
    nlopt_note += "; worst: " + worst;
  }
  res.message = o.algorithm + ", " + nlopt_note;
  return res;
}

}  // namespace marsyn::nlopt_planner
