// The augmented-Lagrangian cost, the violation measure and the multiplier update.
#include "solver.hpp"

#include <algorithm>
#include <cmath>

namespace marsyn::altro::detail {

double Solver::stage_cost(int k, const Vec& x, const Vec* u, Scratch& s, const Vec* z) const {
  double J = 0.0;
  const bool term = k == T_;
  // Without q_state, the same arithmetic as before it existed (plans stay bit-identical).
  if (term) J += 0.5 * opt_.q_terminal * (x - goal_centre_).squaredNorm();
  else if (uniform_q_) J += 0.5 * opt_.q_track * (x - ref_[k]).squaredNorm();
  else J += 0.5 * (q_stage_.array() * (x - ref_[k]).array().square()).sum();
  if (u) {
    J += 0.5 * opt_.r_input * u->squaredNorm();
    for (int j = 0; j < m_; ++j) {
      J += phr(pp_.input_bounds.lo[j] - (*u)[j], lam_ulo_[k][j], rho_);
      J += phr((*u)[j] - pp_.input_bounds.hi[j], lam_uhi_[k][j], rho_);
    }
  }
  if (u && points_ > 0) J += between_cost(k, x, *u, s, z);  // u_0 moves the flow after x0 too
  if (k == 0) return J;  // x0 is fixed: constraints there cannot be influenced
  for (int i = 0; i < n_; ++i) {
    if (std::isfinite(pp_.state_bounds.lo[i])) J += phr(pp_.state_bounds.lo[i] - x[i], lam_xlo_[k][i], rho_);
    if (std::isfinite(pp_.state_bounds.hi[i])) J += phr(x[i] - pp_.state_bounds.hi[i], lam_xhi_[k][i], rho_);
  }
  std::vector<double>& g = s.g;
  screen_->near(x.data(), s.near, s.screen);
  needed(s.near, held_c_[k], s.cand);
  for (int i : s.cand) {
    const auto& r = stage_[i];
    if (!applies_at(*r.c, k, T_)) continue;  // a mission stage's rows: at its visit knots only
    if (static_cast<int>(g.size()) < r.rows) g.resize(r.rows);
    r.c->evaluate(x.data(), g.data(), nullptr);
    for (int j = 0; j < r.rows; ++j) J += phr(g[j], lam_c_[k][r.lam_offset + j], rho_);
  }
  if (term) {
    for (int i = 0; i < n_; ++i) {
      if (std::isfinite(pp_.goal.lo[i])) J += phr(pp_.goal.lo[i] - x[i], lam_glo_[i], rho_);
      if (std::isfinite(pp_.goal.hi[i])) J += phr(x[i] - pp_.goal.hi[i], lam_ghi_[i], rho_);
    }
    for (const auto& r : terminal_) {
      if (static_cast<int>(g.size()) < r.rows) g.resize(r.rows);
      r.c->evaluate(x.data(), g.data(), nullptr);
      for (int j = 0; j < r.rows; ++j) J += phr(g[j], lam_t_[r.lam_offset + j], rho_);
    }
  }
  return J;
}

double Solver::total_cost(const std::vector<Vec>& X, const std::vector<Vec>& U, const std::vector<Vec>* Z) const {
  // Knots on several threads, summed in knot order: the same sum for any number of threads.
  std::vector<double>& c = knot_cost_;
  c.resize(T_ + 1);
  pool_->run(T_ + 1, threads_for(T_ + 1, static_cast<long>(agents_.size())), [&](int t, int begin, int end) {
    for (int k = begin; k < end; ++k)
      c[k] = stage_cost(k, X[k], k < T_ ? &U[k] : nullptr, work_[t], Z && k < T_ ? &(*Z)[k] : nullptr);
  });
  double J = 0.0;
  for (int k = 0; k < T_; ++k) J += c[k];
  return J + c[T_];
}

double Solver::max_violation(const std::vector<Vec>& X, const std::vector<Vec>& U, std::string* worst,
                             const std::vector<Vec>* Z) const {
  double v = 0.0;
  auto note = [&](double c, const std::string& what) {
    if (c > v) {
      v = c;
      if (worst) *worst = what;
    }
  };
  for (int k = 0; k < T_; ++k)
    for (int j = 0; j < m_; ++j) {
      note(pp_.input_bounds.lo[j] - U[k][j], "input bound");
      note(U[k][j] - pp_.input_bounds.hi[j], "input bound");
    }
  std::vector<double> g(64);
  for (int k = 1; k <= T_; ++k) {
    for (int i = 0; i < n_; ++i) {
      note(pp_.state_bounds.lo[i] - X[k][i], "state bound");
      note(X[k][i] - pp_.state_bounds.hi[i], "state bound");
    }
    screen_->near(X[k].data(), near_);  // every other row is satisfied
    for (int c : near_) {
      const auto& r = stage_[c];
      if (!applies_at(*r.c, k, T_)) continue;  // a mission stage's rows: at its visit knots only
      g.resize(std::max<size_t>(g.size(), r.rows));
      r.c->evaluate(X[k].data(), g.data(), nullptr);
      for (int j = 0; j < r.rows; ++j)
        if (g[j] > v) note(g[j], r.c->name() + " at step " + std::to_string(k));
    }
  }
  for (int i = 0; i < n_; ++i) {
    note(pp_.goal.lo[i] - X[T_][i], "goal");
    note(X[T_][i] - pp_.goal.hi[i], "goal");
  }
  for (const auto& r : terminal_) {
    g.resize(std::max<size_t>(g.size(), r.rows));
    r.c->evaluate(X[T_].data(), g.data(), nullptr);
    for (int j = 0; j < r.rows; ++j)
      if (g[j] > v) note(g[j], r.c->name());
  }
  if (points_ > 0) v = between_violation(X, U, Z, worst, v);
  return v;
}

void Solver::update_multipliers() {
  auto upd = [&](double& lam, double c) { lam = std::max(0.0, lam + rho_ * c); };
  std::vector<double> g(64);
  for (int k = 0; k < T_; ++k)
    for (int j = 0; j < m_; ++j) {
      upd(lam_ulo_[k][j], pp_.input_bounds.lo[j] - U_[k][j]);
      upd(lam_uhi_[k][j], U_[k][j] - pp_.input_bounds.hi[j]);
    }
  for (int k = 1; k <= T_; ++k) {
    for (int i = 0; i < n_; ++i) {
      if (std::isfinite(pp_.state_bounds.lo[i])) upd(lam_xlo_[k][i], pp_.state_bounds.lo[i] - X_[k][i]);
      if (std::isfinite(pp_.state_bounds.hi[i])) upd(lam_xhi_[k][i], X_[k][i] - pp_.state_bounds.hi[i]);
    }
    screen_->near(X_[k].data(), near_);
    needed(near_, held_c_[k], cand_);
    for (int c : cand_) {
      const auto& r = stage_[c];
      if (!applies_at(*r.c, k, T_)) continue;  // a mission stage's rows: at its visit knots only
      g.resize(std::max<size_t>(g.size(), r.rows));
      r.c->evaluate(X_[k].data(), g.data(), nullptr);
      for (int j = 0; j < r.rows; ++j) upd(lam_c_[k][r.lam_offset + j], g[j]);
    }
  }
  for (int i = 0; i < n_; ++i) {
    if (std::isfinite(pp_.goal.lo[i])) upd(lam_glo_[i], pp_.goal.lo[i] - X_[T_][i]);
    if (std::isfinite(pp_.goal.hi[i])) upd(lam_ghi_[i], X_[T_][i] - pp_.goal.hi[i]);
  }
  for (const auto& r : terminal_) {
    g.resize(std::max<size_t>(g.size(), r.rows));
    r.c->evaluate(X_[T_].data(), g.data(), nullptr);
    for (int j = 0; j < r.rows; ++j) upd(lam_t_[r.lam_offset + j], g[j]);
  }
  if (points_ > 0) update_between_multipliers();
  hold();
}

void Solver::hold() {
  auto held = [](const std::vector<ConstraintRef>& list, const double* lam, std::vector<int>& out) {
    out.clear();
    for (int c = 0; c < static_cast<int>(list.size()); ++c)
      for (int j = 0; j < list[c].rows; ++j)
        if (lam[list[c].lam_offset + j] != 0.0) {
          out.push_back(c);
          break;
        }
  };
  held_c_.resize(lam_c_.size());
  for (std::size_t k = 0; k < lam_c_.size(); ++k) held(stage_, lam_c_[k].data(), held_c_[k]);
  held_b_.resize(lam_b_.size() * static_cast<std::size_t>(points_));
  for (std::size_t k = 0; k < lam_b_.size(); ++k)
    for (int j = 0; j < points_; ++j)
      held(between_, lam_b_[k].data() + static_cast<long>(j) * between_rows_, held_b_[k * points_ + j]);
}

}  // namespace marsyn::altro::detail
