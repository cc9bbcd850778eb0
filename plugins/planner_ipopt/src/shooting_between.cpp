// The requirements between the samples (PlanningProblem::between) in the multiple-shooting NLP:
// rows g(z_j(x_k, u_k)) <= 0 at the interior points of every period, after the terminal rows.
// Each row reads x_k (k >= 1; x_0 is fixed) and u_k of the agents its constraint reads. Its
// Hessian block is exact: the constraint's curvature carried through the partial step's
// Jacobian, Jz' (sum lambda g'') Jz, plus the flow's own, (sum lambda g_z) z'', whose second
// derivatives come from the same AD as the defects' blocks.
#include <algorithm>
#include <cmath>

#include "marsyn/sampled_map.hpp"
#include "shooting_nlp.hpp"

namespace marsyn::ipopt_planner {

void ShootingNlp::setup_between() {
  points_ = model_.points;
  if (points_ == 0) return;
  std::vector<int> agent_of(n_);
  for (int i = 0; i < static_cast<int>(model_.agents.size()); ++i)
    for (int c = 0; c < model_.agents[i].n; ++c) agent_of[model_.agents[i].xo + c] = i;
  for (const auto& c : model_.pp.between) {
    Between b{c.get(), between_rows_, {}};
    for (int s : c->support())
      if (std::find(b.agents.begin(), b.agents.end(), agent_of[s]) == b.agents.end()) b.agents.push_back(agent_of[s]);
    between_rows_ += c->size();
    between_.push_back(std::move(b));
  }
}

std::vector<int> ShootingNlp::between_vars(const Between& b, int k) const {
  std::vector<int> vars;
  for (int ai : b.agents) {
    const auto& a = model_.agents[ai];
    if (k >= 1)
      for (int i = 0; i < a.n; ++i) vars.push_back(xvar(k, a.xo + i));
    for (int c = 0; c < a.m; ++c) vars.push_back(uvar(k, a.uo + c));
  }
  return vars;
}

int ShootingNlp::between_row(int k, int j, const Between& b) const {
  return T_ * n_ + T_ * path_rows_ + terminal_rows_ + (k * points_ + j - 1) * between_rows_ + b.offset;
}

void ShootingNlp::between_patterns() {
  for (int k = 0; k < T_; ++k)
    for (int j = 1; j <= points_; ++j)
      for (const auto& b : between_) {
        const auto vars = between_vars(b, k);
        const int row0 = between_row(k, j, b);
        for (int r = 0; r < b.c->size(); ++r)
          for (int v : vars) {
            jrow_.push_back(row0 + r);
            jcol_.push_back(v);
          }
        for (size_t p = 0; p < vars.size(); ++p)
          for (size_t q = 0; q <= p; ++q) {
            hrow_.push_back(std::max(vars[p], vars[q]));
            hcol_.push_back(std::min(vars[p], vars[q]));
          }
      }
}

void ShootingNlp::interior_at(const Number* z, int k, int j, bool jacobians) {
  point_.resize(n_);
  const double* x = state(z, k);
  const double* u = z + uvar(k, 0);
  const int N = static_cast<int>(model_.agents.size());
  zA_.resize(N);
  zB_.resize(N);
  for (int i = 0; i < N; ++i) {
    const auto& a = model_.agents[i];
    zA_[i].resize(static_cast<size_t>(a.n) * a.n);
    zB_[i].resize(static_cast<size_t>(a.n) * a.m);
    flow_point(*a.dyn, x + a.xo, u + a.uo, model_.tau, model_.substeps, j, points_, point_.data() + a.xo,
               jacobians ? zA_[i].data() : nullptr, jacobians ? zB_[i].data() : nullptr);
  }
}

// Jz: d z / d(vars of the row), one row per support entry, in between_vars' column order.
Eigen::MatrixXd ShootingNlp::between_jz(const Between& b, int k) const {
  const auto& sup = b.c->support();
  int cols = 0;
  for (int ai : b.agents) cols += (k >= 1 ? model_.agents[ai].n : 0) + model_.agents[ai].m;
  Eigen::MatrixXd Jz = Eigen::MatrixXd::Zero(static_cast<long>(sup.size()), cols);
  for (size_t e = 0; e < sup.size(); ++e) {
    int col = 0;
    for (int ai : b.agents) {
      const auto& a = model_.agents[ai];
      const int li = sup[e] - a.xo;
      const bool mine = li >= 0 && li < a.n;
      if (k >= 1) {
        if (mine)
          for (int i = 0; i < a.n; ++i) Jz(static_cast<long>(e), col + i) = zA_[ai][li * a.n + i];
        col += a.n;
      }
      if (mine)
        for (int c = 0; c < a.m; ++c) Jz(static_cast<long>(e), col + c) = zB_[ai][li * a.m + c];
      col += a.m;
    }
  }
  return Jz;
}

void ShootingNlp::between_g(const Number* z, Number* g) {
  for (int k = 0; k < T_; ++k)
    for (int j = 1; j <= points_; ++j) {
      interior_at(z, k, j, false);
      for (const auto& b : between_)
        b.c->evaluate(point_.data(), g + between_row(k, j, b), nullptr);
    }
}

size_t ShootingNlp::between_jacobian(const Number* z, Number* v) {
  size_t e = 0;
  std::vector<double> g, jac;
  for (int k = 0; k < T_; ++k)
    for (int j = 1; j <= points_; ++j) {
      interior_at(z, k, j, true);
      for (const auto& b : between_) {
        const int rows = b.c->size(), w = static_cast<int>(b.c->support().size());
        g.resize(rows);
        jac.resize(static_cast<size_t>(rows) * w);
        b.c->evaluate(point_.data(), g.data(), jac.data());
        const Eigen::MatrixXd Jz = between_jz(b, k);
        for (int r = 0; r < rows; ++r) {
          const Eigen::Map<const Eigen::RowVectorXd> gz(jac.data() + static_cast<size_t>(r) * w, w);
          const Eigen::RowVectorXd row = gz * Jz;
          for (long c = 0; c < row.size(); ++c) v[e++] = row[c];
        }
      }
    }
  return e;
}

size_t ShootingNlp::between_hessian(const Number* z, const Number* lambda, bool exact, Number* v) {
  size_t e = 0;
  std::vector<double> gz, jz;
  for (int k = 0; k < T_; ++k)
    for (int j = 1; j <= points_; ++j) {
      interior_at(z, k, j, true);
      for (const auto& b : between_) {
        const int w = static_cast<int>(b.c->support().size());
        const double* lam = lambda + between_row(k, j, b);
        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> H =
            Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>::Zero(w, w);
        if (!(exact && constraint_hessian(*b.c, point_.data(), lam, H.data())))
          differenced_constraint_hessian(*b.c, point_.data(), n_, lam, H.data());
        ++blocks_.between;
        const Eigen::MatrixXd Jz = between_jz(b, k);
        Eigen::MatrixXd M = Jz.transpose() * H * Jz;
        // The flow's own curvature: sum_i (sum_r lambda_r dg_r/dz_i) d^2 z_i / d(x, u)^2, per
        // agent, the same second derivatives as the defects' blocks over the partial step.
        const int rows = b.c->size();
        gz.resize(rows);
        jz.resize(static_cast<size_t>(rows) * w);
        b.c->evaluate(point_.data(), gz.data(), jz.data());
        const FlowPointStep step = flow_point_step(model_.tau, model_.substeps, j, points_);
        const double* x = state(z, k);
        const double* u = z + uvar(k, 0);
        int col = 0;
        for (int ai : b.agents) {
          const auto& a = model_.agents[ai];
          std::vector<double> wts(a.n, 0.0);
          const auto& sup = b.c->support();
          for (int s = 0; s < w; ++s) {
            const int li = sup[s] - a.xo;
            if (li < 0 || li >= a.n) continue;
            for (int r = 0; r < rows; ++r) wts[li] += lam[r] * jz[static_cast<size_t>(r) * w + s];
          }
          const int aw = a.n + a.m, first = k >= 1 ? 0 : a.n;
          std::vector<double> Hf(static_cast<size_t>(aw) * aw, 0.0);
          if (exact && fields_[ai])
            rk4_weighted_hessian(fields_[ai], a.n, a.m, x + a.xo, u + a.uo, wts.data(), step.h, step.substeps, Hf.data());
          else
            differenced_dynamics_hessian(*a.dyn, x + a.xo, u + a.uo, wts.data(), step.h, step.substeps, first, Hf.data());
          const int span = aw - first;
          for (int p = 0; p < span; ++p)
            for (int q = 0; q < span; ++q) M(col + p, col + q) += Hf[static_cast<size_t>(first + p) * aw + first + q];
          col += span;
        }
        for (long p = 0; p < M.rows(); ++p)
          for (long q = 0; q <= p; ++q) v[e++] = M(p, q);
      }
    }
  return e;
}

}  // namespace marsyn::ipopt_planner
