#include "marsyn/planner_support/product_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "marsyn/sampled_map.hpp"

namespace marsyn::planner_support {

void RowSet::add_lower(int coord, double lo) {
  items_.push_back({nullptr, coord, -1.0, lo});
  rows_ += 1;
  nnz_ += 1;
}
void RowSet::add_upper(int coord, double hi) {
  items_.push_back({nullptr, coord, 1.0, hi});
  rows_ += 1;
  nnz_ += 1;
}
void RowSet::add(const Constraint* c) {
  items_.push_back({c, -1, 0.0, 0.0});
  rows_ += c->size();
  nnz_ += c->size() * static_cast<int>(c->support().size());
}

void RowSet::pattern(std::vector<int>& row, std::vector<int>& col) const {
  row.clear();
  col.clear();
  int r = 0;
  for (const auto& it : items_) {
    if (!it.c) {
      row.push_back(r++);
      col.push_back(it.coord);
      continue;
    }
    const auto& s = it.c->support();
    for (int i = 0; i < it.c->size(); ++i, ++r)
      for (int j : s) {
        row.push_back(r);
        col.push_back(j);
      }
  }
}

void RowSet::evaluate(const double* x, double* g, double* jac, int knot) const {
  int r = 0, e = 0;
  for (const auto& it : items_) {
    if (it.c && knot >= 0 && !applies_at(*it.c, knot, std::numeric_limits<int>::max())) {
      const int rows = it.c->size(), w = static_cast<int>(it.c->support().size());
      std::fill(g + r, g + r + rows, -1.0);
      if (jac) std::fill(jac + e, jac + e + rows * w, 0.0);
      r += rows;
      e += rows * w;
      continue;
    }
    if (!it.c) {
      // lo - x (sign -1) or x - hi (sign +1)
      g[r++] = it.sign * (x[it.coord] - it.bound);
      if (jac) jac[e] = it.sign;
      ++e;
      continue;
    }
    const int rows = it.c->size(), w = static_cast<int>(it.c->support().size());
    it.c->evaluate(x, g + r, jac ? jac + e : nullptr);
    r += rows;
    e += rows * w;
  }
}

void RowSet::dense(const double* jac, Eigen::MatrixXd& J) const {
  J.setZero();
  int r = 0, e = 0;
  for (const auto& it : items_) {
    if (!it.c) {
      J(r++, it.coord) = jac[e++];
      continue;
    }
    const auto& s = it.c->support();
    for (int i = 0; i < it.c->size(); ++i, ++r)
      for (int j : s) J(r, j) += jac[e++];
  }
}

double RowSet::worst(const double* x, std::string* name, int knot) const {
  scratch_g_.resize(std::max(rows_, 1));
  evaluate(x, scratch_g_.data(), nullptr, knot);
  double v = -INFINITY;
  int r = 0;
  for (const auto& it : items_) {
    const int rows = it.c ? it.c->size() : 1;
    for (int i = 0; i < rows; ++i, ++r)
      if (scratch_g_[r] > v) {
        v = scratch_g_[r];
        if (name)
          *name = it.c ? it.c->name()
                       : std::string(it.sign < 0 ? "lower bound of " : "upper bound of ") +
                             (it.coord < static_cast<int>(coord_names_.size()) ? coord_names_[static_cast<std::size_t>(it.coord)]
                                                                                : "x" + std::to_string(it.coord));
      }
  }
  return v;
}

Eigen::VectorXd goal_centre(const PlanningProblem& pp) {
  Eigen::VectorXd c(pp.goal.dim());
  for (int i = 0; i < c.size(); ++i) {
    const double lo = pp.goal.lo[i], hi = pp.goal.hi[i];
    c[i] = std::isfinite(lo) && std::isfinite(hi) ? 0.5 * (lo + hi) : std::isfinite(lo) ? lo : std::isfinite(hi) ? hi : pp.x0[i];
  }
  return c;
}

ProductModel::ProductModel(const PlanningProblem& p) : pp(p) {
  const Problem& prob = *pp.problem;
  tau = prob.tau;
  substeps = prob.rk4_substeps;
  T = pp.horizon;
  const ProductLayout layout(prob);
  for (std::size_t i = 0; i < prob.agents.size(); ++i) {
    const AgentSpec& a = prob.agents[i];
    agents.push_back({a.dynamics.get(), layout.state[i], layout.input[i], a.n(), a.m()});
  }
  n = layout.state_dim();
  m = layout.input_dim();
  std::vector<std::string> names(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < prob.agents.size(); ++i) {
    const AgentSpec& a = prob.agents[i];
    const auto states = a.dynamics ? a.dynamics->state_names() : std::vector<std::string>{};
    for (int c = 0; c < a.n(); ++c)
      names[static_cast<std::size_t>(layout.state[i] + c)] =
          (c < static_cast<int>(states.size()) ? states[static_cast<std::size_t>(c)] : "x" + std::to_string(c)) + " of " + a.name;
  }
  path.name_coordinates(names);
  between.name_coordinates(names);
  for (auto& s : names) s += " (goal)";
  terminal.name_coordinates(std::move(names));
  for (int i = 0; i < n; ++i) {
    if (std::isfinite(pp.state_bounds.lo[i])) path.add_lower(i, pp.state_bounds.lo[i]);
    if (std::isfinite(pp.state_bounds.hi[i])) path.add_upper(i, pp.state_bounds.hi[i]);
  }
  for (int i = 0; i < n; ++i) {
    if (std::isfinite(pp.goal.lo[i])) terminal.add_lower(i, pp.goal.lo[i]);
    if (std::isfinite(pp.goal.hi[i])) terminal.add_upper(i, pp.goal.hi[i]);
  }
  goal_centre = planner_support::goal_centre(pp);
  for (const auto& c : pp.constraints) (c->stage() == ConstraintStage::Terminal ? terminal : path).add(c.get());
  points = pp.between.empty() ? 0 : std::max(0, pp.between_points);
  if (points > 0)
    for (const auto& c : pp.between) between.add(c.get());
}

void ProductModel::interior(const double* x, const double* u, int j, double* z) const {
  for (const auto& a : agents)
    flow_point(*a.dyn, x + a.xo, u + a.uo, tau, substeps, j, points, z + a.xo, nullptr, nullptr);
}

void ProductModel::interior_jacobians(const double* x, const double* u, int j, Eigen::MatrixXd& A,
                                      Eigen::MatrixXd& B) const {
  A.setZero(n, n);
  B.setZero(n, m);
  double z[kMaxDual], Ar[kMaxDual * kMaxDual], Br[kMaxDual * kMaxDual];
  for (const auto& a : agents) {
    flow_point(*a.dyn, x + a.xo, u + a.uo, tau, substeps, j, points, z, Ar, Br);
    for (int i = 0; i < a.n; ++i) {
      for (int c = 0; c < a.n; ++c) A(a.xo + i, a.xo + c) = Ar[i * a.n + c];
      for (int c = 0; c < a.m; ++c) B(a.xo + i, a.uo + c) = Br[i * a.m + c];
    }
  }
}

void ProductModel::step(const double* x, const double* u, double* out) const {
  // The exact check re-simulates with the same function, so plans here reproduce bit for bit.
  for (const auto& a : agents) rk4_step<double>(*a.dyn, x + a.xo, u + a.uo, nullptr, tau, substeps, out + a.xo);
}

void ProductModel::jacobians(const double* x, const double* u, Eigen::MatrixXd& A, Eigen::MatrixXd& B) const {
  A.setZero(n, n);
  B.setZero(n, m);
  double Ar[kMaxDual * kMaxDual], Br[kMaxDual * kMaxDual];
  for (const auto& a : agents) {
    rk4_jacobians(*a.dyn, x + a.xo, u + a.uo, tau, substeps, nullptr, Ar, Br);
    for (int i = 0; i < a.n; ++i) {
      for (int j = 0; j < a.n; ++j) A(a.xo + i, a.xo + j) = Ar[i * a.n + j];
      for (int j = 0; j < a.m; ++j) B(a.xo + i, a.uo + j) = Br[i * a.m + j];
    }
  }
}

std::vector<Eigen::VectorXd> ProductModel::rollout(const std::vector<Eigen::VectorXd>& U) const {
  std::vector<Eigen::VectorXd> X(U.size() + 1, Eigen::VectorXd(n));
  X[0] = pp.x0;
  for (size_t k = 0; k < U.size(); ++k) step(X[k].data(), U[k].data(), X[k + 1].data());
  return X;
}

double ProductModel::violation(const std::vector<Eigen::VectorXd>& X, const std::vector<Eigen::VectorXd>& U,
                               std::string* worst) const {
  double v = 0.0;
  std::string w;
  for (const auto& u : U)
    for (int j = 0; j < m; ++j) {
      const double e = std::max(pp.input_bounds.lo[j] - u[j], u[j] - pp.input_bounds.hi[j]);
      if (e > v) v = e, w = "input bound";
    }
  for (size_t k = 1; k < X.size(); ++k) {
    std::string name;
    const double e = path.worst(X[k].data(), &name, static_cast<int>(k));
    if (e > v) v = e, w = name + " at k = " + std::to_string(k);
  }
  if (terminal.rows() > 0) {
    std::string name;
    const double e = terminal.worst(X.back().data(), &name);
    if (e > v) v = e, w = name + " at the end";
  }
  if (points > 0 && between.rows() > 0) {
    Eigen::VectorXd z(n);
    for (size_t k = 0; k + 1 < X.size() && k < U.size(); ++k)
      for (int j = 1; j <= points; ++j) {
        interior(X[k].data(), U[k].data(), j, z.data());
        std::string name;
        const double e = between.worst(z.data(), &name);
        if (e > v) v = e, w = name + " between k = " + std::to_string(k) + " and " + std::to_string(k + 1);
      }
  }
  if (worst) *worst = w;
  return v;
}

std::vector<Eigen::VectorXd> ProductModel::initial_inputs() const {
  std::vector<Eigen::VectorXd> U(T, Eigen::VectorXd::Zero(m));
  const bool warm = pp.warm_start && static_cast<int>(pp.warm_start->u.size()) >= T;
  for (int k = 0; k < T; ++k)
    for (int j = 0; j < m; ++j)
      U[k][j] = std::clamp(warm ? pp.warm_start->u[k][j] : 0.0, pp.input_bounds.lo[j], pp.input_bounds.hi[j]);
  return U;
}

}  // namespace marsyn::planner_support
