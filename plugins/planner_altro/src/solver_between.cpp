// The requirements between the samples (PlanningProblem::between): rows at the interior points
// z_j = phi(x_k, u_k, j) of every period, which depend on the step's input as well as its state.
// They enter the augmented Lagrangian like the stage rows; their Gauss-Newton model adds blocks
// in u and (u, x) to the stage's quadratic model (LuuT_, LuxT_, stored transposed), which the
// backward pass adds to Quu and Qux.
#include <algorithm>
#include <cmath>
#include <functional>

#include "marsyn/sampled_map.hpp"
#include "rk4.hpp"
#include "solver.hpp"

namespace marsyn::altro::detail {

void Solver::interior_points(const Vec& x, const Vec& u, Vec& Z) const {
  Z.resize(static_cast<long>(points_) * n_);
  double tmp[kMaxDual * 16];
  for (const auto& a : agents_) {
    double* buf = points_ * a.n <= kMaxDual * 16 ? tmp : nullptr;
    std::vector<double> heap;
    if (!buf) heap.resize(static_cast<size_t>(points_) * a.n), buf = heap.data();
    flow_points(*a.dyn, x.data() + a.xo, u.data() + a.uo, prob_.tau, prob_.rk4_substeps, points_, buf);
    for (int j = 0; j < points_; ++j)
      for (int c = 0; c < a.n; ++c) Z[static_cast<long>(j) * n_ + a.xo + c] = buf[j * a.n + c];
  }
}

const Vec& Solver::points_at(int k, const std::vector<Vec>& X, const std::vector<Vec>& U, const std::vector<Vec>* Z,
                             Vec& tmp) const {
  if (Z) return (*Z)[k];
  interior_points(X[k], U[k], tmp);
  return tmp;
}

double Solver::between_cost(int k, const Vec& x, const Vec& u, Scratch& s, const Vec* zk) const {
  double J = 0.0;
  std::vector<double>& g = s.g;
  if (!zk) interior_points(x, u, s.z);
  const Vec& Z = zk ? *zk : s.z;
  for (int j = 1; j <= points_; ++j) {
    const double* z = Z.data() + static_cast<long>(j - 1) * n_;
    const double* lam = lam_b_[k].data() + static_cast<long>(j - 1) * between_rows_;
    screen_b_->near(z, s.near, s.screen);
    needed(s.near, held_b_[static_cast<std::size_t>(k) * points_ + j - 1], s.cand);
    for (int c : s.cand) {
      const auto& r = between_[c];
      if (static_cast<int>(g.size()) < r.rows) g.resize(r.rows);
      r.c->evaluate(z, g.data(), nullptr);
      for (int i = 0; i < r.rows; ++i) J += phr(g[i], lam[r.lam_offset + i], rho_);
    }
  }
  return J;
}

void Solver::for_each_between_row(const std::vector<Vec>& X, const std::vector<Vec>& U, const std::vector<Vec>* Zs,
                                  const std::function<void(int k, int j, const ConstraintRef& r, const double* g)>& f) const {
  // Rows the screen leaves out are satisfied and carry no multiplier: f would change nothing.
  std::vector<double> g(64);
  Vec tmp;
  for (int k = 0; k < T_; ++k) {
    const Vec& Z = points_at(k, X, U, Zs, tmp);
    for (int j = 1; j <= points_; ++j) {
      const double* z = Z.data() + static_cast<long>(j - 1) * n_;
      screen_b_->near(z, near_);
      needed(near_, held_b_[static_cast<std::size_t>(k) * points_ + j - 1], cand_);
      for (int c : cand_) {
        const auto& r = between_[c];
        g.resize(std::max<size_t>(g.size(), r.rows));
        r.c->evaluate(z, g.data(), nullptr);
        f(k, j, r, g.data());
      }
    }
  }
}

double Solver::between_violation(const std::vector<Vec>& X, const std::vector<Vec>& U, const std::vector<Vec>* Z,
                                 std::string* worst, double v) const {
  for_each_between_row(X, U, Z, [&](int k, int, const ConstraintRef& r, const double* g) {
    for (int i = 0; i < r.rows; ++i)
      if (g[i] > v) {
        v = g[i];
        if (worst) *worst = r.c->name() + " between steps " + std::to_string(k) + " and " + std::to_string(k + 1);
      }
  });
  return v;
}

void Solver::update_between_multipliers() {
  for_each_between_row(X_, U_, kept(Z_), [&](int k, int j, const ConstraintRef& r, const double* g) {
    double* lam = lam_b_[k].data() + static_cast<long>(j - 1) * between_rows_ + r.lam_offset;
    for (int i = 0; i < r.rows; ++i) lam[i] = std::max(0.0, lam[i] + rho_ * g[i]);
  });
}

void Solver::between_gradients(int k, int j, const ConstraintRef& r, const double* jac, int row,
                               std::vector<AgentGradient>& out, Scratch& s) const {
  out.clear();
  const auto& sup = r.c->support();
  const FlowPointStep step = flow_point_step(prob_.tau, prob_.rk4_substeps, j, points_);
  const double* J = jac + static_cast<size_t>(row) * sup.size();
  for (size_t e = 0; e < sup.size(); ++e) {
    if (J[e] == 0.0) continue;
    const int ai = agent_of_[sup[e]];
    const auto& a = agents_[ai];
    if (!s.have_jac[ai] && kept_mid_jacobians_) {  // linearize() saw this iterate
      s.AB[ai] = mid_jac_.data() + k * mid_stride_ + mid_at_[ai];
      s.have_jac[ai] = 1;
    }
    if (!s.have_jac[ai]) {
      std::vector<double>& own = s.own[ai];
      own.resize(static_cast<size_t>(a.n) * (a.n + a.m));
      rk4_jacobians_staged(*a.dyn, X_[k].data() + a.xo, U_[k].data() + a.uo, step.h, step.substeps, own.data(),
                           own.data() + a.n * a.n, a.reads);
      s.AB[ai] = own.data();
      s.have_jac[ai] = 1;
    }
    auto it = std::find_if(out.begin(), out.end(), [&](const AgentGradient& g) { return g.agent == ai; });
    if (it == out.end()) {
      out.push_back({ai, Vec::Zero(a.n), Vec::Zero(a.m)});
      it = out.end() - 1;
    }
    const int li = sup[e] - a.xo;
    it->cx.noalias() += J[e] * Eigen::Map<const Vec>(s.AB[ai] + li * a.n, a.n);
    it->cu.noalias() += J[e] * Eigen::Map<const Vec>(s.AB[ai] + a.n * a.n + li * a.m, a.m);
  }
}

void Solver::expand_between(int k, Scratch& s) {
  const int G = static_cast<int>(groups_.size());
  // Most periods have no active between row, and an active row reads one or two agents: only the
  // rows of Luu and Lux of the agents written to are zeroed (when first written) and added in
  // the backward pass (a ten-drone group's blocks are 20 x 20 and 20 x 30).
  for (int gi = 0; gi < G; ++gi) between_agents_[k * G + gi].clear();
  std::vector<double>& g = s.g;
  std::vector<double>& jac = s.jac;
  std::vector<AgentGradient>& grads = s.grads;
  const Vec& Z = points_at(k, X_, U_, kept(Z_), s.z);
  for (int j = 1; j <= points_; ++j) {
    const double* z = Z.data() + static_cast<long>(j - 1) * n_;
    std::fill(s.have_jac.begin(), s.have_jac.end(), 0);
    const double* lam = lam_b_[k].data() + static_cast<long>(j - 1) * between_rows_;
    screen_b_->near(z, s.near, s.screen);
    needed(s.near, held_b_[static_cast<std::size_t>(k) * points_ + j - 1], s.cand);
    for (int c : s.cand) {
      const auto& r = between_[c];
      g.resize(std::max<size_t>(g.size(), r.rows));
      r.c->evaluate(z, g.data(), nullptr);
      bool any = false;
      for (int i = 0; i < r.rows; ++i) any |= lam[r.lam_offset + i] + rho_ * g[i] > 0;
      if (!any) continue;
      jac.resize(static_cast<size_t>(r.rows) * r.c->support().size());
      r.c->evaluate(z, g.data(), jac.data());
      // As for the stage rows: cross-group blocks dropped, kept ones scaled by the groups touched.
      const double scale = rho_ * r.groups_touched;
      for (int i = 0; i < r.rows; ++i) {
        const double mu = lam[r.lam_offset + i] + rho_ * g[i];
        if (mu <= 0) continue;
        between_gradients(k, j, r, jac.data(), i, grads, s);
        for (const auto& ga : grads) {
          const auto& a = agents_[ga.agent];
          const int gi = a.group;
          const auto& gr = groups_[gi];
          const int xa = a.xo - gr.xo, ua = a.uo - gr.uo;
          auto& touched = between_agents_[k * G + gi];
          if (std::find(touched.begin(), touched.end(), ga.agent) == touched.end()) {
            touched.push_back(ga.agent);
            if (LuuT_[k * G + gi].cols() != gr.m) LuuT_[k * G + gi].resize(gr.m, gr.m);
            if (LuxT_[k * G + gi].cols() != gr.m) LuxT_[k * G + gi].resize(gr.n, gr.m);
            LuuT_[k * G + gi].middleCols(ua, a.m).setZero();
            LuxT_[k * G + gi].middleCols(ua, a.m).setZero();
          }
          lx_[k * G + gi].segment(xa, a.n) += mu * ga.cx;
          lu_[k * G + gi].segment(ua, a.m) += mu * ga.cu;
          for (const auto& gb : grads) {
            const auto& b = agents_[gb.agent];
            if (b.group != gi) continue;
            const int xb = b.xo - gr.xo, ub = b.uo - gr.uo;
            lxx_[k * G + gi].block(xa, xb, a.n, b.n).noalias() += scale * ga.cx * gb.cx.transpose();
            // Entry (ub + j, ua + i) is cu_b[j] (scale cu_a[i]): Luu's (ua + i, ub + j) bit for bit.
            LuuT_[k * G + gi].block(ub, ua, b.m, a.m).noalias() += gb.cu * (scale * ga.cu).transpose();
            LuxT_[k * G + gi].block(xb, ua, b.n, a.m).noalias() += gb.cx * (scale * ga.cu).transpose();
          }
        }
      }
    }
  }
}

}  // namespace marsyn::altro::detail
