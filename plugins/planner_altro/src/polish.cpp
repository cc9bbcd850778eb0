#include "solver.hpp"

#include <algorithm>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "inequality_step.hpp"
#include "input_pieces.hpp"

namespace marsyn::altro::detail {

// The between rows of every period k (dc/dx_k, swept back like a state row at step k, and
// dc/du_k) at the interior points, near-active ones only: the screen's for rows above -active
// (ProximityScreen::near with a level), the same rows in the same order as the whole list
// gives, without evaluating every pair at every point (at 1000 robots the projection evaluated
// 6e5 rows per knot and took 58 % of the plan).
void Solver::between_polish_rows(double active, std::vector<PolishRow>& rows) {
  std::vector<double> g(64), jac;
  std::vector<AgentGradient> grads;
  Vec tmp;
  Scratch& s = work_[0];
  for (int k = 0; k < T_; ++k) {
    const Vec& Z = points_at(k, X_, U_, kept(Z_), tmp);
    for (int j = 1; j <= points_; ++j) {
      const double* z = Z.data() + static_cast<long>(j - 1) * n_;
      std::fill(s.have_jac.begin(), s.have_jac.end(), 0);
      screen_b_->near(z, s.near, s.screen, active);
      for (const int c : s.near) {
        const ConstraintRef& r = between_[c];
        g.resize(std::max<size_t>(g.size(), r.rows));
        r.c->evaluate(z, g.data(), nullptr);
        bool any = false;
        for (int i = 0; i < r.rows; ++i) any |= g[i] > -active;
        if (!any) continue;
        jac.resize(static_cast<size_t>(r.rows) * r.c->support().size());
        r.c->evaluate(z, g.data(), jac.data());
        for (int i = 0; i < r.rows; ++i) {
          if (g[i] <= -active) continue;
          between_gradients(k, j, r, jac.data(), i, grads, s);
          PolishRow row{k, g[i], {}, false};
          for (const auto& ga : grads) {
            const auto& a = agents_[ga.agent];
            for (int c = 0; c < a.n; ++c) row.grad.push_back({a.xo + c, ga.cx[c]});
            for (int c = 0; c < a.m; ++c) row.ugrad.push_back({a.uo + c, ga.cu[c]});
          }
          rows.push_back(std::move(row));
        }
      }
    }
  }
}

// The near-active input bounds, state bounds, goal rows and constraint rows.
void Solver::bound_polish_rows(double active, std::vector<PolishRow>& rows) {
  auto take = [&](int k, double c, std::vector<std::pair<int, double>> g, bool input) {
    if (c > -active) rows.push_back({k, c, std::move(g), input});
  };
  std::vector<double> g(64), jac;
  for (int k = 0; k < T_; ++k)
    for (int j = 0; j < m_; ++j) {
      take(k, pp_.input_bounds.lo[j] - U_[k][j], {{j, -1.0}}, true);
      take(k, U_[k][j] - pp_.input_bounds.hi[j], {{j, 1.0}}, true);
    }
  for (int k = 1; k <= T_; ++k) {
    const Vec& x = X_[k];
    for (int i = 0; i < n_; ++i) {
      take(k, pp_.state_bounds.lo[i] - x[i], {{i, -1.0}}, false);
      take(k, x[i] - pp_.state_bounds.hi[i], {{i, 1.0}}, false);
      if (k == T_) {
        take(k, pp_.goal.lo[i] - x[i], {{i, -1.0}}, false);
        take(k, x[i] - pp_.goal.hi[i], {{i, 1.0}}, false);
      }
    }
    auto add = [&](const ConstraintRef& r) {
      g.resize(std::max<size_t>(g.size(), r.rows));
      r.c->evaluate(x.data(), g.data(), nullptr);
      bool any = false;
      for (int j = 0; j < r.rows; ++j) any |= g[j] > -active;
      if (!any) return;
      const auto& sup = r.c->support();
      jac.resize(static_cast<size_t>(r.rows) * sup.size());
      r.c->evaluate(x.data(), g.data(), jac.data());
      for (int j = 0; j < r.rows; ++j) {
        std::vector<std::pair<int, double>> gr;
        for (size_t a = 0; a < sup.size(); ++a) gr.push_back({sup[a], jac[j * sup.size() + a]});
        take(k, g[j], std::move(gr), false);
      }
    };
    // The screen's rows above -active (between_polish_rows says why).
    screen_->near(x.data(), work_[0].near, work_[0].screen, active);
    for (const int c : work_[0].near)
      if (applies_at(*stage_[c].c, k, T_)) add(stage_[c]);
    if (k == T_)
      for (const auto& r : terminal_) add(r);
  }
}

// dU = J' y, the least-norm change with c + J dU <= 0 for the rows to first order
// (inequality_step.hpp); false when the work is over its cap or the solve fails.
bool Solver::polish_direction(const std::vector<PolishRow>& rows, Vec& dU) const {
  const int N = static_cast<int>(agents_.size());
  // J is sparse (input_pieces.hpp): per row and agent it reads, the gradient in that agent's
  // inputs up to the row's step (a 50-agent swap: 853 rows, 1.2e10 for the dense J J', which
  // skipped the projection; 1.8e7 by agent).
  std::vector<InputPiece> pieces;
  std::vector<double> values;
  std::vector<int> input_agent(m_);
  for (int i = 0; i < N; ++i)
    for (int c = 0; c < agents_[i].m; ++c) input_agent[agents_[i].uo + c] = i;
  // The piece of (row r, agent ai) covering steps 0..last, created zero on first use.
  std::vector<long> piece_of(N, -1);
  auto piece = [&](int r, int ai, int last) -> double* {
    if (piece_of[ai] < 0) {
      piece_of[ai] = static_cast<long>(pieces.size());
      pieces.push_back({r, ai, last, static_cast<long>(values.size())});
      values.resize(values.size() + static_cast<size_t>(last + 1) * agents_[ai].m, 0.0);
    }
    return values.data() + pieces[piece_of[ai]].at;
  };
  Vec v = Vec::Zero(n_);
  std::vector<int> who;
  for (size_t r = 0; r < rows.size(); ++r) {
    const PolishRow& row = rows[r];
    const int ri = static_cast<int>(r);
    const size_t first_piece = pieces.size();
    if (row.input) {
      for (const auto& [j, d] : row.grad) {
        const int ai = input_agent[j];
        piece(ri, ai, row.k)[static_cast<long>(row.k) * agents_[ai].m + j - agents_[ai].uo] += d;
      }
    } else {
      // A between row reads u_k directly: its pieces reach step k, a state row's step k - 1.
      const int last = row.ugrad.empty() ? row.k - 1 : row.k;
      who.clear();
      for (const auto& [i, d] : row.grad)
        if (std::find(who.begin(), who.end(), agent_of_[i]) == who.end()) who.push_back(agent_of_[i]);
      for (const auto& [j, d] : row.ugrad)
        if (std::find(who.begin(), who.end(), input_agent[j]) == who.end()) who.push_back(input_agent[j]);
      if (last >= 0)
        for (int ai : who) piece(ri, ai, last);
      for (const auto& [j, d] : row.ugrad) {
        const int ai = input_agent[j];
        values[pieces[piece_of[ai]].at + static_cast<long>(row.k) * agents_[ai].m + j - agents_[ai].uo] += d;
      }
      // Adjoint sweep restricted to the agents the row reads (the dynamics do not couple them).
      for (const auto& [i, d] : row.grad) v[i] += d;
      for (int j = row.k - 1; j >= 0; --j)
        for (int ai : who) {
          const auto& a = agents_[ai];
          Eigen::Map<Vec>(values.data() + pieces[piece_of[ai]].at + static_cast<long>(j) * a.m, a.m) =
              B_[j * N + ai].transpose() * v.segment(a.xo, a.n);
          v.segment(a.xo, a.n) = A_[j * N + ai].transpose() * v.segment(a.xo, a.n);
        }
      for (int ai : who) v.segment(agents_[ai].xo, agents_[ai].n).setZero();
    }
    for (size_t p = first_piece; p < pieces.size(); ++p) piece_of[pieces[p].agent] = -1;
  }
  std::vector<int> inputs_of(N), input_offset(N);
  for (int i = 0; i < N; ++i) inputs_of[i] = agents_[i].m, input_offset[i] = agents_[i].uo;
  if (gram_work(pieces, inputs_of, T_) > opt_.polish_max_work) return false;
  const long R = static_cast<long>(rows.size());
  const Eigen::SparseMatrix<double> M = gram_by_agent(pieces, values, inputs_of, static_cast<int>(R));
  // Rows at neighbouring interior points and knots are nearly parallel: a little damping keeps
  // the least-norm step from blowing up on them (1e-12 without them, as before).
  const double damp = (points_ > 0 ? 1e-8 : 1e-12) * (1.0 + (R > 0 ? M.diagonal().maxCoeff() : 0.0));
  Vec c(R), y;
  for (long r = 0; r < R; ++r) c[r] = rows[r].c;
  if (!inequality_step(M, c, damp, opt_.polish_active_rounds, y)) return false;
  dU = Vec::Zero(static_cast<long>(T_) * m_);
  add_transpose_times(pieces, values, inputs_of, input_offset, m_, y, dU);
  if (!dU.allFinite()) return false;
  return true;
}

// Backtracking along dU from the current iterate: the first step that lowers the violation is
// taken (viol, worst updated); false when none does.
bool Solver::polish_line_search(const Vec& dU, double& viol, std::string& worst) {
  bool improved = false;
  for (double alpha = 1.0; alpha > 1e-3 && !improved; alpha *= 0.5) {
    Xn_[0] = X_[0];
    for (int k = 0; k < T_; ++k) {
      Un_[k] = U_[k] + alpha * dU.segment(static_cast<long>(k) * m_, m_);
      for (const auto& a : agents_) step_agent(a, Xn_[k], Un_[k], Xn_[k + 1], kept_points_ ? &Zn_[k] : nullptr);
    }
    std::string w;
    const double nv = max_violation(Xn_, Un_, &w, kept(Zn_));
    if (nv < viol) {
      std::swap(X_, Xn_);
      std::swap(U_, Un_);
      std::swap(Z_, Zn_);
      viol = nv;
      worst = w;
      improved = true;
    }
  }
  return improved;
}

// The augmented Lagrangian approaches feasibility only as fast as the penalty grows; this step
// finishes the job. With the near-active rows c_i (violated or within `active` of their bound) as
// functions of the inputs, it takes the least-norm input change that drives the violated rows to
// zero and keeps the others satisfied to first order: dU = J' y (inequality_step.hpp), where row i
// of J is dc_i/dU by an adjoint sweep through the block-diagonal Jacobians.
bool Solver::polish(double& viol, std::string& worst, const Stopwatch& clock) {
  const double active = 1e-3;
  for (int it = 0; it < opt_.polish_iterations && viol > opt_.constraint_tolerance; ++it) {
    if (clock.seconds() > run_.time_limit_s) return false;
    linearize();
    std::vector<PolishRow> rows;
    if (points_ > 0) between_polish_rows(active, rows);
    bound_polish_rows(active, rows);
    if (rows.empty()) return false;
    Vec dU;
    if (!polish_direction(rows, dU)) return false;
    if (!polish_line_search(dU, viol, worst)) return false;
  }
  return viol <= opt_.constraint_tolerance;
}

}  // namespace marsyn::altro::detail
