#include "shooting_nlp.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/QR>

#include "marsyn/stopwatch.hpp"
#include "marsyn/sampled_map.hpp"

namespace marsyn::ipopt_planner {

namespace {
constexpr double kIpoptInf = 2e19;  // beyond Ipopt's default nlp_{lower,upper}_bound_inf
double finite_or(double v, double inf) { return std::isfinite(v) ? v : inf; }
}  // namespace

ShootingNlp::ShootingNlp(const planner_support::ProductModel& model, const Options& options, const PlanOptions& run, Stopwatch clock,
                         std::vector<SecondOrderField> fields)
    : model_(model), o_(options), run_(run), clock_(clock), T_(model.T), n_(model.n), m_(model.m), fields_(std::move(fields)) {
  fields_.resize(model_.agents.size());
  for (size_t i = 0; i < fields_.size(); ++i)
    if (!fields_[i]) fields_[i] = second_order_field(*model_.agents[i].dyn);
  for (const auto& c : model_.pp.constraints) {
    if (c->stage() == ConstraintStage::Terminal) {
      terminal_.push_back(c.get());
      terminal_rows_ += c->size();
    } else {
      path_.push_back(c.get());
      path_rows_ += c->size();
    }
  }
  setup_between();
  build_patterns();
}

void ShootingNlp::build_patterns() {
  // Jacobian: defects, then path rows per step, then terminal rows.
  const int N = static_cast<int>(model_.agents.size());
  for (int k = 0; k < T_; ++k)
    for (int i = 0; i < N; ++i) {
      const auto& a = model_.agents[i];
      for (int r = 0; r < a.n; ++r) {
        const int row = k * n_ + a.xo + r;
        jrow_.push_back(row);
        jcol_.push_back(xvar(k + 1, a.xo + r));
        if (k >= 1)
          for (int b = 0; b < a.n; ++b) {
            jrow_.push_back(row);
            jcol_.push_back(xvar(k, a.xo + b));
          }
        for (int c = 0; c < a.m; ++c) {
          jrow_.push_back(row);
          jcol_.push_back(uvar(k, a.uo + c));
        }
      }
    }
  auto rows_of = [&](const std::vector<const Constraint*>& list, int base, int k) {
    for (const auto* c : list) {
      for (int r = 0; r < c->size(); ++r)
        for (int s : c->support()) {
          jrow_.push_back(base + r);
          jcol_.push_back(xvar(k, s));
        }
      base += c->size();
    }
  };
  for (int k = 1; k <= T_; ++k) rows_of(path_, T_ * n_ + (k - 1) * path_rows_, k);
  rows_of(terminal_, T_ * n_ + T_ * path_rows_, T_);

  // Hessian (lower triangle; Ipopt sums duplicate entries): one dense block per step and agent
  // over (x_k^i, u_k^i), one per constraint and step over its support, the cost's diagonal.
  for (int k = 0; k < T_; ++k)
    for (const auto& a : model_.agents) {
      std::vector<int> vars;
      if (k >= 1)
        for (int b = 0; b < a.n; ++b) vars.push_back(xvar(k, a.xo + b));
      for (int c = 0; c < a.m; ++c) vars.push_back(uvar(k, a.uo + c));
      for (size_t p = 0; p < vars.size(); ++p)
        for (size_t q = 0; q <= p; ++q) {
          hrow_.push_back(std::max(vars[p], vars[q]));
          hcol_.push_back(std::min(vars[p], vars[q]));
        }
    }
  auto blocks_of = [&](const std::vector<const Constraint*>& list, int k) {
    for (const auto* c : list) {
      const auto& s = c->support();
      for (size_t p = 0; p < s.size(); ++p)
        for (size_t q = 0; q <= p; ++q) {
          hrow_.push_back(std::max(xvar(k, s[p]), xvar(k, s[q])));
          hcol_.push_back(std::min(xvar(k, s[p]), xvar(k, s[q])));
        }
    }
  };
  for (int k = 1; k <= T_; ++k) blocks_of(path_, k);
  blocks_of(terminal_, T_);
  for (int i = 0; i < n_; ++i) {
    hrow_.push_back(xvar(T_, i));
    hcol_.push_back(xvar(T_, i));
  }
  between_patterns();  // Jacobian rows and Hessian blocks, after everything above
}

bool ShootingNlp::get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& style) {
  n = T_ * (n_ + m_);
  m = T_ * n_ + T_ * path_rows_ + terminal_rows_ + T_ * points_ * between_rows_;
  nnz_jac_g = static_cast<Index>(jrow_.size());
  nnz_h_lag = static_cast<Index>(hrow_.size());
  style = C_STYLE;
  return true;
}

bool ShootingNlp::get_bounds_info(Index, Number* x_l, Number* x_u, Index, Number* g_l, Number* g_u) {
  const auto& pp = model_.pp;
  for (int k = 1; k <= T_; ++k)
    for (int i = 0; i < n_; ++i) {
      double lo = pp.state_bounds.lo[i], hi = pp.state_bounds.hi[i];
      if (k == T_) {
        lo = std::isfinite(lo) ? std::max(lo, pp.goal.lo[i]) : pp.goal.lo[i];
        hi = std::isfinite(hi) ? std::min(hi, pp.goal.hi[i]) : pp.goal.hi[i];
      }
      x_l[xvar(k, i)] = finite_or(lo, -kIpoptInf);
      x_u[xvar(k, i)] = finite_or(hi, kIpoptInf);
    }
  for (int k = 0; k < T_; ++k)
    for (int j = 0; j < m_; ++j) {
      x_l[uvar(k, j)] = pp.input_bounds.lo[j];
      x_u[uvar(k, j)] = pp.input_bounds.hi[j];
    }
  const int defects = T_ * n_, total = defects + T_ * path_rows_ + terminal_rows_ + T_ * points_ * between_rows_;
  for (int r = 0; r < defects; ++r) g_l[r] = g_u[r] = 0.0;
  for (int r = defects; r < total; ++r) {
    g_l[r] = -kIpoptInf;
    g_u[r] = 0.0;
  }
  // A constraint that applies at some knots only (a mission stage's visit): its rows elsewhere
  // are free (Ipopt drops bounds beyond nlp_upper_bound_inf).
  for (int k = 1; k <= T_; ++k) {
    int r = defects + (k - 1) * path_rows_;
    for (const auto* c : path_) {
      if (!applies_at(*c, k, T_))
        for (int i = 0; i < c->size(); ++i) g_u[r + i] = kIpoptInf;
      r += c->size();
    }
  }
  return true;
}

bool ShootingNlp::get_starting_point(Index, bool, Number* z, bool, Number*, Number*, Index, bool, Number*) {
  const auto& pp = model_.pp;
  const bool warm = pp.warm_start && static_cast<int>(pp.warm_start->u.size()) >= T_;
  const auto U = model_.initial_inputs();
  for (int k = 0; k < T_; ++k)
    for (int j = 0; j < m_; ++j) z[uvar(k, j)] = U[k][j];
  if (warm || o_.initial_guess == "rollout") {
    // The warm start's own states may be missing or stale: re-simulate its inputs.
    const auto X = model_.rollout(U);
    for (int k = 1; k <= T_; ++k)
      for (int i = 0; i < n_; ++i) z[xvar(k, i)] = X[k][i];
    return true;
  }
  // Straight lines to the goal centre, each agent's bent sideways by a slightly different amount:
  // crossing straight lines give a symmetric guess with no feasible neighbour in that symmetry.
  std::vector<Eigen::VectorXd> X(T_ + 1);
  for (int k = 0; k <= T_; ++k) X[k] = pp.x0 + (static_cast<double>(k) / T_) * (model_.goal_centre - pp.x0);
  const auto& agents = pp.problem->agents;
  const int N = static_cast<int>(agents.size());
  for (int i = 0; i < N; ++i) {
    const auto& ws = agents[i].workspace;
    if (!ws.linear() || ws.index[0] < 0 || ws.index[1] < 0) continue;
    const int ix = model_.agents[i].xo + ws.index[0], iy = model_.agents[i].xo + ws.index[1];
    const Eigen::Vector2d d(model_.goal_centre[ix] - pp.x0[ix], model_.goal_centre[iy] - pp.x0[iy]);
    const double len = d.norm();
    if (len < 1e-9) continue;
    const double amp = o_.bend * len * (1.0 + 0.2 * i / std::max(1, N - 1));
    for (int k = 0; k <= T_; ++k) {
      const double b = amp * std::sin(M_PI * k / T_);
      X[k][ix] += -b * d.y() / len;
      X[k][iy] += b * d.x() / len;
    }
  }
  for (int k = 1; k <= T_; ++k)
    for (int i = 0; i < n_; ++i) {
      double v = X[k][i];
      const double lo = pp.state_bounds.lo[i], hi = pp.state_bounds.hi[i];
      if (std::isfinite(lo)) v = std::max(v, lo);
      if (std::isfinite(hi)) v = std::min(v, hi);
      X[k][i] = z[xvar(k, i)] = v;
    }
  if (o_.fit_inputs) {
    // Inputs that best explain each step of the guess: two Gauss-Newton steps on
    // |x_{k+1} - f_tau(x_k, u)|, clamped to U. Zero inputs under moving states leave every
    // defect open, and Ipopt's restoration phase can then stall (docs/benchmarks-planners.md).
    Eigen::MatrixXd A, B;
    Eigen::VectorXd next(n_), u(m_);
    for (int k = 0; k < T_; ++k) {
      for (int j = 0; j < m_; ++j) u[j] = z[uvar(k, j)];
      for (int it = 0; it < 2; ++it) {
        model_.jacobians(X[k].data(), u.data(), A, B);
        model_.step(X[k].data(), u.data(), next.data());
        u += B.colPivHouseholderQr().solve(X[k + 1] - next);
        for (int j = 0; j < m_; ++j) u[j] = std::clamp(u[j], pp.input_bounds.lo[j], pp.input_bounds.hi[j]);
      }
      for (int j = 0; j < m_; ++j) z[uvar(k, j)] = u[j];
    }
  }
  return true;
}

bool ShootingNlp::eval_f(Index, const Number* z, bool, Number& obj) {
  double J = 0.0;
  for (int k = 0; k < T_; ++k)
    for (int j = 0; j < m_; ++j) J += 0.5 * o_.r_input * z[uvar(k, j)] * z[uvar(k, j)];
  for (int i = 0; i < n_; ++i) {
    const double e = z[xvar(T_, i)] - model_.goal_centre[i];
    J += 0.5 * o_.q_terminal * e * e;
  }
  obj = J;
  return true;
}

bool ShootingNlp::eval_grad_f(Index n, const Number* z, bool, Number* g) {
  std::fill(g, g + n, 0.0);
  for (int k = 0; k < T_; ++k)
    for (int j = 0; j < m_; ++j) g[uvar(k, j)] = o_.r_input * z[uvar(k, j)];
  for (int i = 0; i < n_; ++i) g[xvar(T_, i)] = o_.q_terminal * (z[xvar(T_, i)] - model_.goal_centre[i]);
  return true;
}

void ShootingNlp::linearize(const Number* z) {
  const size_t nz = static_cast<size_t>(T_) * (n_ + m_);
  if (z_cache_.size() == nz && std::equal(z_cache_.begin(), z_cache_.end(), z)) return;
  z_cache_.assign(z, z + nz);
  const int N = static_cast<int>(model_.agents.size());
  next_.assign(T_, Eigen::VectorXd(n_));
  jac_.resize(static_cast<size_t>(T_) * N);
  double A[kMaxDual * kMaxDual], B[kMaxDual * kMaxDual];
  for (int k = 0; k < T_; ++k) {
    const double* x = state(z, k);
    const double* u = z + uvar(k, 0);
    for (int i = 0; i < N; ++i) {
      const auto& a = model_.agents[i];
      rk4_jacobians(*a.dyn, x + a.xo, u + a.uo, model_.tau, model_.substeps, next_[k].data() + a.xo, A, B);
      auto& J = jac_[k * N + i];
      J.resize(static_cast<size_t>(a.n) * (a.n + a.m));
      for (int r = 0; r < a.n; ++r) {
        for (int b = 0; b < a.n; ++b) J[r * (a.n + a.m) + b] = A[r * a.n + b];
        for (int c = 0; c < a.m; ++c) J[r * (a.n + a.m) + a.n + c] = B[r * a.m + c];
      }
    }
  }
}

bool ShootingNlp::eval_g(Index, const Number* z, bool, Index, Number* g) {
  // Defects use the same RK4 arithmetic as the exact check's re-simulation.
  std::vector<double> next(n_);
  for (int k = 0; k < T_; ++k) {
    model_.step(state(z, k), z + uvar(k, 0), next.data());
    for (int i = 0; i < n_; ++i) g[k * n_ + i] = z[xvar(k + 1, i)] - next[i];
  }
  auto rows_of = [&](const std::vector<const Constraint*>& list, int base, int k) {
    for (const auto* c : list) {
      c->evaluate(state(z, k), g + base, nullptr);
      base += c->size();
    }
  };
  for (int k = 1; k <= T_; ++k) rows_of(path_, T_ * n_ + (k - 1) * path_rows_, k);
  rows_of(terminal_, T_ * n_ + T_ * path_rows_, T_);
  if (points_ > 0) between_g(z, g);
  return true;
}

bool ShootingNlp::eval_jac_g(Index, const Number* z, bool, Index, Index, Index* iRow, Index* jCol, Number* v) {
  if (!v) {
    std::copy(jrow_.begin(), jrow_.end(), iRow);
    std::copy(jcol_.begin(), jcol_.end(), jCol);
    return true;
  }
  linearize(z);
  const int N = static_cast<int>(model_.agents.size());
  size_t e = 0;
  for (int k = 0; k < T_; ++k)
    for (int i = 0; i < N; ++i) {
      const auto& a = model_.agents[i];
      const auto& J = jac_[k * N + i];
      for (int r = 0; r < a.n; ++r) {
        v[e++] = 1.0;
        if (k >= 1)
          for (int b = 0; b < a.n; ++b) v[e++] = -J[r * (a.n + a.m) + b];
        for (int c = 0; c < a.m; ++c) v[e++] = -J[r * (a.n + a.m) + a.n + c];
      }
    }
  std::vector<double> g(16);
  auto rows_of = [&](const std::vector<const Constraint*>& list, int k) {
    for (const auto* c : list) {
      g.resize(std::max<size_t>(g.size(), c->size()));
      c->evaluate(state(z, k), g.data(), v + e);
      e += static_cast<size_t>(c->size()) * c->support().size();
    }
  };
  for (int k = 1; k <= T_; ++k) rows_of(path_, k);
  rows_of(terminal_, T_);
  if (points_ > 0) e += between_jacobian(z, v + e);
  return true;
}

bool ShootingNlp::eval_h(Index, const Number* z, bool, Number sigma, Index, const Number* lambda, bool, Index,
                         Index* iRow, Index* jCol, Number* v) {
  if (!v) {
    std::copy(hrow_.begin(), hrow_.end(), iRow);
    std::copy(hcol_.begin(), hcol_.end(), jCol);
    return true;
  }
  const Stopwatch h_clock;
  const bool exact = o_.hessian == "exact";
  blocks_ = {};
  size_t e = 0;
  hess_.resize(std::max<size_t>(hess_.size(), kMaxDual * kMaxDual));
  double* H = hess_.data();
  // Dynamics: the defect x_{k+1} - f_tau(x_k, u_k) is linear in x_{k+1}, so its curvature is
  // -lambda_k' f_tau'' over (x_k^i, u_k^i), per agent; plus the input cost on the diagonal.
  for (int k = 0; k < T_; ++k) {
    const double* x = state(z, k);
    const double* u = z + uvar(k, 0);
    for (size_t i = 0; i < model_.agents.size(); ++i) {
      const auto& a = model_.agents[i];
      const int w = a.n + a.m, first = k >= 1 ? 0 : a.n;  // x_0 is not a variable
      const double* lam = lambda + k * n_ + a.xo;
      if (exact && fields_[i]) {
        rk4_weighted_hessian(fields_[i], a.n, a.m, x + a.xo, u + a.uo, lam, model_.tau, model_.substeps, H);
        ++blocks_.dynamics_exact;
      } else {
        differenced_dynamics_hessian(*a.dyn, x + a.xo, u + a.uo, lam, model_.tau, model_.substeps, first, H);
        ++blocks_.dynamics_differenced;
      }
      for (int p = first; p < w; ++p)
        for (int q = first; q <= p; ++q) v[e++] = -H[p * w + q] + (p == q && p >= a.n ? sigma * o_.r_input : 0.0);
    }
  }
  // Constraints: lambda' g(x_k) over each support.
  auto blocks_of = [&](const std::vector<const Constraint*>& list, int base, int k) {
    for (const auto* c : list) {
      const int w = static_cast<int>(c->support().size());
      hess_.resize(std::max<size_t>(hess_.size(), static_cast<size_t>(w) * w));
      H = hess_.data();
      std::fill(H, H + w * w, 0.0);
      if (exact && constraint_hessian(*c, state(z, k), lambda + base, H)) {
        ++blocks_.constraints_exact;
      } else {
        differenced_constraint_hessian(*c, state(z, k), n_, lambda + base, H);
        ++blocks_.constraints_differenced;
      }
      for (int p = 0; p < w; ++p)
        for (int q = 0; q <= p; ++q) v[e++] = H[p * w + q];
      base += c->size();
    }
  };
  for (int k = 1; k <= T_; ++k) blocks_of(path_, T_ * n_ + (k - 1) * path_rows_, k);
  blocks_of(terminal_, T_ * n_ + T_ * path_rows_, T_);
  for (int i = 0; i < n_; ++i) v[e++] = sigma * o_.q_terminal;
  if (points_ > 0) e += between_hessian(z, lambda, exact, v + e);
  ++h_evals_;
  h_seconds_ += h_clock.seconds();
  return true;
}

bool ShootingNlp::intermediate_callback(Ipopt::AlgorithmMode, Index iter, Number obj, Number inf_pr, Number,
                                        Number, Number, Number, Number, Number, Index, const Ipopt::IpoptData*,
                                        Ipopt::IpoptCalculatedQuantities*) {
  iterations_ = iter;
  if (run_.progress) run_.progress({static_cast<int>(iter), obj, inf_pr});
  // Wall-clock limit (Ipopt 3.11's max_cpu_time counts CPU time).
  if (clock_.seconds() > run_.time_limit_s) {
    timed_out_ = true;
    return false;
  }
  return true;
}

void ShootingNlp::finalize_solution(Ipopt::SolverReturn status, Index, const Number* z, const Number*,
                                    const Number*, Index, const Number*, const Number*, Number,
                                    const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) {
  status_ = status;
  solution_u_.assign(T_, Eigen::VectorXd(m_));
  for (int k = 0; k < T_; ++k)
    for (int j = 0; j < m_; ++j) solution_u_[k][j] = z[uvar(k, j)];
}

}  // namespace marsyn::ipopt_planner
