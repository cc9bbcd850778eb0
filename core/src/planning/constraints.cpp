#include "marsyn/core/planning/constraints.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "marsyn/dual.hpp"

namespace marsyn::planning {

void workspace_point_jacobian(const AgentSpec& agent, const double* x, double* p, double* J) {
  const int n = agent.n();
  const auto& ws = agent.workspace;
  if (ws.linear()) {
    workspace_point(*agent.dynamics, ws, x, p);
    if (J) {
      for (int i = 0; i < ws.dim() * n; ++i) J[i] = 0.0;
      for (int c = 0; c < ws.dim(); ++c)
        if (ws.index[c] >= 0) J[c * n + ws.index[c]] = 1.0;
    }
    return;
  }
  if (!J) {
    agent.dynamics->footprint(ws.footprint, x, p);
    return;
  }
  std::vector<DualD> xd(n);
  for (int i = 0; i < n; ++i) xd[i] = DualD::variable(x[i], i, n);
  DualD pd[2];
  agent.dynamics->footprint(ws.footprint, xd.data(), pd);
  for (int c = 0; c < 2; ++c) {
    p[c] = pd[c].v;
    for (int i = 0; i < n; ++i) J[c * n + i] = pd[c].derivative(i);
  }
}

namespace {

std::vector<int> range_support(int off_a, int n_a, int off_b = 0, int n_b = 0) {
  std::vector<int> s;
  for (int i = 0; i < n_a; ++i) s.push_back(off_a + i);
  for (int i = 0; i < n_b; ++i) s.push_back(off_b + i);
  return s;
}

// d = p_a - p_b and its Jacobians (D x n_a, D x n_b) for a constraint on agents a, b, D the
// workspace dimension (the agents share it); d[2] = 0 in the plane.
struct PairGeometry {
  int D = 2;
  double d[kMaxWorkspaceDim] = {0, 0, 0};
  double Ja[kMaxWorkspaceDim * kMaxDual], Jb[kMaxWorkspaceDim * kMaxDual];
  PairGeometry(const AgentSpec& a, const AgentSpec& b, const double* xa, const double* xb, bool jac)
      : D(a.workspace.dim()) {
    double pa[kMaxWorkspaceDim], pb[kMaxWorkspaceDim];
    workspace_point_jacobian(a, xa, pa, jac ? Ja : nullptr);
    workspace_point_jacobian(b, xb, pb, jac ? Jb : nullptr);
    for (int c = 0; c < D; ++c) d[c] = pa[c] - pb[c];
  }
  // Row of dg/dx given dg/dd (the plane's expression unchanged).
  void chain(const double* gd, int na, int nb, double* row) const {
    for (int i = 0; i < na; ++i) row[i] = gd[0] * Ja[i] + gd[1] * Ja[na + i];
    for (int i = 0; i < nb; ++i) row[na + i] = -(gd[0] * Jb[i] + gd[1] * Jb[nb + i]);
    if (D == 3) {
      for (int i = 0; i < na; ++i) row[i] += gd[2] * Ja[2 * na + i];
      for (int i = 0; i < nb; ++i) row[na + i] -= gd[2] * Jb[2 * nb + i];
    }
  }
  double norm() const { return D == 2 ? std::hypot(d[0], d[1]) : std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]); }
};


// H (cols x cols, row-major) += D' S D with D = [J_a, -J_b] (W x cols) and S symmetric W x W,
// W the workspace dimension.
void add_congruence(const double* Ja, int na, const double* Jb, int nb, const double* S, double* H, int W = 2) {
  const int cols = na + nb;
  double D[kMaxWorkspaceDim * 2 * kMaxDual];
  for (int c = 0; c < W; ++c) {
    for (int i = 0; i < na; ++i) D[c * cols + i] = Ja[c * na + i];
    for (int i = 0; i < nb; ++i) D[c * cols + na + i] = -Jb[c * nb + i];
  }
  for (int p = 0; p < cols; ++p)
    for (int q = 0; q < cols; ++q) {
      double v = 0.0;
      for (int r = 0; r < W; ++r)
        for (int t = 0; t < W; ++t) v += D[r * cols + p] * S[r * W + t] * D[t * cols + q];
      H[p * cols + q] += v;
    }
}

// (I - n n') / |d|: the second derivative of the Euclidean norm at d != 0 (W x W).
void norm_curvature(const double* d, double scale, double* S, int W = 2) {
  const double len = W == 2 ? std::hypot(d[0], d[1]) : std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (len < 1e-12) {
    for (int i = 0; i < W * W; ++i) S[i] = 0.0;
    return;
  }
  double n[kMaxWorkspaceDim];
  for (int c = 0; c < W; ++c) n[c] = d[c] / len;
  for (int r = 0; r < W; ++r)
    for (int t = 0; t < W; ++t) S[r * W + t] = scale * (r == t ? 1 - n[r] * n[r] : -n[r] * n[t]) / len;
}

// P[c] (n x n, row-major, P = 2 x n x n) = d^2 p_c / dx^2 of the agent's workspace point: zero
// for a linear workspace, forward-over-forward AD of the footprint otherwise. False when the
// model has no second-order evaluation.
bool footprint_hessian(const AgentSpec& a, const double* x, double* P) {
  const int n = a.n();
  std::fill(P, P + 2 * n * n, 0.0);
  if (a.workspace.linear()) return true;
  if (!a.dynamics->has_second_order()) return false;
  DualD2 xd[kMaxDual], pd[2];
  for (int i = 0; i < n; ++i) xd[i] = second_order_variable(x[i], i, n);
  a.dynamics->footprint(a.workspace.footprint, xd, pd);
  for (int c = 0; c < 2; ++c)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) P[(c * n + i) * n + j] = second_derivative(pd[c], i, j);
  return true;
}

// H (cols = na + nb) += the workspace points' own curvature for d = p_a - p_b, given the
// weighted gradient gw = sum_r w_r dg_r/dd (so dg/dp_a = gw, dg/dp_b = -gw) and P from
// footprint_hessian.
void add_footprint_curvature(const double* Pa, int na, const double* Pb, int nb, const double gw[2], double* H) {
  const int cols = na + nb;
  for (int c = 0; c < 2; ++c) {
    for (int i = 0; i < na; ++i)
      for (int j = 0; j < na; ++j) H[i * cols + j] += gw[c] * Pa[(c * na + i) * na + j];
    for (int i = 0; i < nb; ++i)
      for (int j = 0; j < nb; ++j) H[(na + i) * cols + na + j] -= gw[c] * Pb[(c * nb + i) * nb + j];
  }
}

}  // namespace

ObstacleConstraint::ObstacleConstraint(std::string name, const AgentSpec& agent, int offset, Polygon obstacle,
                                       std::shared_ptr<const MarginTable> margins, double grow, double clearance,
                                       const DistanceModelFactory& distance)
    : name_(std::move(name)), agent_(&agent), support_(range_support(offset, agent.n())),
      obstacle_(std::move(obstacle)), margins_(std::move(margins)), grow_(grow), clearance_(clearance) {
  if (margins_->constant()) {
    grown_ = grow_by_box(obstacle_, margins_->max().x + grow_, margins_->max().y + grow_);
    grown_edges_ = PolygonEdges(grown_);
    if (distance) distance_ = distance({grown_});
  }
}

void ObstacleConstraint::set_z(double z_lo, double z_hi) {
  z_lo_ = z_lo;
  z_hi_ = z_hi;
  // A collision plugin's distance is the polygon's: a prism bounded in z is core's.
  if (prism()) distance_.reset();
}

void ObstacleConstraint::evaluate(const double* x, double* g, double* jac) const {
  const int n = agent_->n();
  const double* xa = x + support_[0];
  double p[kMaxWorkspaceDim];
  double J[kMaxWorkspaceDim * kMaxDual];
  workspace_point_jacobian(*agent_, xa, p, jac ? J : nullptr);
  if (prism()) {
    // The prism grown by the margin box (+ grow): the grown polygon times the grown interval.
    const WorkspaceMargin m = margins_->at(xa);
    const double zg = m.z + grow_;
    Eigen::Vector3d grad;
    const double sd = margins_->constant()
                          ? signed_distance(grown_edges_, z_lo_ - zg, z_hi_ + zg, Eigen::Vector3d(p[0], p[1], p[2]), &grad)
                          : signed_distance(grow_by_box(obstacle_, m.x + grow_, m.y + grow_), z_lo_ - zg, z_hi_ + zg,
                                            Eigen::Vector3d(p[0], p[1], p[2]), &grad);
    g[0] = clearance_ - sd;
    if (jac)
      for (int i = 0; i < n; ++i) jac[i] = -(grad[0] * J[i] + grad[1] * J[n + i] + grad[2] * J[2 * n + i]);
    return;
  }
  Eigen::Vector2d grad;
  double sd;
  if (distance_) {
    sd = distance_->distance(0, p, grad.data());
  } else if (margins_->constant()) {
    sd = signed_distance(grown_edges_, Eigen::Vector2d(p[0], p[1]), &grad);
  } else {
    const WorkspaceMargin m = margins_->at(xa);
    sd = signed_distance(grow_by_box(obstacle_, m.x + grow_, m.y + grow_), Eigen::Vector2d(p[0], p[1]), &grad);
  }
  g[0] = clearance_ - sd;
  if (jac)
    for (int i = 0; i < n; ++i) jac[i] = -(grad[0] * J[i] + grad[1] * J[n + i]);
}

bool ObstacleConstraint::clear_outside(double lo[2], double hi[2]) const {
  if (!margins_->constant() || distance_ || grown_.empty()) return false;
  double scale = 1.0 + std::abs(clearance_);
  for (int c = 0; c < 2; ++c) {
    lo[c] = hi[c] = grown_.front()[c];
    for (const auto& v : grown_) {
      lo[c] = std::min(lo[c], v[c]);
      hi[c] = std::max(hi[c], v[c]);
    }
    scale = std::max({scale, std::abs(lo[c]), std::abs(hi[c])});
  }
  // A point beyond the box by more than the clearance in x or y is that far from every point of
  // the polygon (a prism's distance is at least its polygon's): g = clearance - sd < 0 there. The
  // widening covers the rounding of sd and of the workspace point the screen compares.
  const double widen = std::max(clearance_, 0.0) + 1e-9 * scale;
  for (int c = 0; c < 2; ++c) {
    lo[c] -= widen;
    hi[c] += widen;
  }
  return std::isfinite(lo[0]) && std::isfinite(lo[1]) && std::isfinite(hi[0]) && std::isfinite(hi[1]);
}

bool ObstacleConstraint::hessian(const double* x, const double* w, double* H) const {
  // A nonlinear footprint adds a curvature term this class cannot evaluate; a state-dependent
  // margin has no fixed grown polygon.
  if (!agent_->workspace.linear() || !margins_->constant()) return false;
  // A prism's distance mixes the polygon's and the interval's: the planner differences the
  // Jacobian there.
  if (prism()) return false;
  const int n = agent_->n();
  double p[kMaxWorkspaceDim], J[kMaxWorkspaceDim * kMaxDual];
  workspace_point_jacobian(*agent_, x + support_[0], p, J);
  // sd is the distance to the nearest edge (linear in p) unless the nearest feature is a vertex
  // v outside, where it is |p - v|. The Hessian is taken on core's grown polygon also when a
  // distance plugin supplies the value: both describe the same polygon.
  const Eigen::Vector2d q(p[0], p[1]);
  const double sd = signed_distance(grown_edges_, q);
  if (sd <= 0) return true;
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d nearest;
  for (const auto& v : grown_)
    if ((q - v).norm() < best) {
      best = (q - v).norm();
      nearest = v;
    }
  if (best - sd > 1e-12 * (1.0 + sd)) return true;  // an edge is nearer: sd is linear here
  const double d[2] = {q.x() - nearest.x(), q.y() - nearest.y()};
  double S[4];
  norm_curvature(d, -w[0], S);  // g = clearance - sd
  double zero[2 * kMaxDual] = {};
  add_congruence(J, n, zero, 0, S, H);
  return true;
}

PairConstraint::PairConstraint(std::string name, const AgentSpec& a, int offset_a, const AgentSpec& b,
                               int offset_b, Norm norm, double delta, std::shared_ptr<const MarginTable> ma,
                               std::shared_ptr<const MarginTable> mb, double corner, double buffer)
    : name_(std::move(name)), a_(&a), b_(&b), support_(range_support(offset_a, a.n(), offset_b, b.n())),
      norm_(norm), delta_(delta), ma_(std::move(ma)), mb_(std::move(mb)), corner_(corner), buffer_(buffer),
      reach_(std::numeric_limits<double>::infinity()) {
  // The distance in the max norm beyond which g <= 0 for every state (see pair_reach); only with
  // constant margins (a table of footprint margins would have to be evaluated cell by cell).
  if (!ma_->constant() || !mb_->constant()) return;
  const WorkspaceMargin m1 = ma_->max(), m2 = mb_->max();
  const double slack = std::max(0.0, buffer_);
  double reach;
  // The rate at which g falls beyond the reach (reach_decay): g <= decay (reach - |d|_inf), from
  // the same bounds (2-norm: g = R - |d|_2 <= R - |d|_inf; max norm: g = s (1 - M) + buffer with
  // M >= |d|_inf / max r - 4c/27 (8c/27 in space), so g <= (s / max r) (reach - |d|_inf)).
  double decay;
  if (norm_ == Norm::Two) {
    reach = delta_ + m1.two() + m2.two() + slack;  // |d|_2 >= |d|_inf
    decay = 1.0;
  } else if (a.workspace.dim() == 3) {
    // The 3-D max nests two smoothed maxima, each at most 4c/27 below the max it smooths.
    const double rx = delta_ + m1.x + m2.x, ry = delta_ + m1.y + m2.y, rz = delta_ + m1.z + m2.z;
    const double s = std::min({rx, ry, rz});
    if (!(s > 0)) return;
    reach = std::max({rx, ry, rz}) * (1.0 + 8.0 * corner_ / 27.0 + slack / s);
    decay = s / std::max({rx, ry, rz});
  } else {
    // value(): g = s (1 - M) + buffer with s = min(rx, ry) and M >= max(|dx|/rx, |dy|/ry) - 4c/27
    // (the smoothed |z| never falls more than 4c/27 below |z|), so g <= 0 once
    // |d|_inf >= max(rx, ry) (1 + 4c/27 + buffer / s).
    const double rx = delta_ + m1.x + m2.x, ry = delta_ + m1.y + m2.y, s = std::min(rx, ry);
    if (!(s > 0)) return;
    reach = std::max(rx, ry) * (1.0 + 4.0 * corner_ / 27.0 + slack / s);
    decay = s / std::max(rx, ry);
  }
  // Outward against the rounding of the sums above and of |p_a - p_b| in the planner.
  reach_ = reach * (1.0 + 1e-9) + 1e-12;
  decay_ = decay * (1.0 - 1e-9);
}

double PairConstraint::value(const double* d, const double* xa, const double* xb, double* gd) const {
  // The margins are piecewise constant in the state: their variation is not differentiated.
  const WorkspaceMargin m1 = ma_->at(xa), m2 = mb_->at(xb);
  const bool space = a_->workspace.dim() == 3;
  if (norm_ == Norm::Two) {
    const double len = space ? std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) : std::hypot(d[0], d[1]);
    const double inv = len > 1e-12 ? 1.0 / len : 0.0;
    gd[0] = -d[0] * inv;
    gd[1] = -d[1] * inv;
    if (space) gd[2] = -d[2] * inv;
    return delta_ + m1.two() + m2.two() + buffer_ - len;
  }
  if (space) return value_inf3(d, m1, m2, gd);
  const double rx = delta_ + m1.x + m2.x, ry = delta_ + m1.y + m2.y;
  const double sx = d[0] / rx, sy = d[1] / ry;
  const double ax = std::abs(sx), ay = std::abs(sy);
  // M(a, b) = (a + b)/2 + sigma((a - b)/2) <= max(a, b), where sigma is |z| smoothed below on
  // |z| < c by z^2 (2c - |z|) / c^2 (C1, never above |z|): exact unless |a - b| < 2c.
  const double z = 0.5 * (ax - ay), az = std::abs(z), c = corner_;
  double sigma = az, dsigma = z >= 0 ? 1.0 : -1.0;
  if (az < c) {
    sigma = z * z * (2 * c - az) / (c * c);
    dsigma = (z >= 0 ? 1.0 : -1.0) * (4 * c * az - 3 * z * z) / (c * c);
  }
  const double M = 0.5 * (ax + ay) + sigma;
  const double dMx = (0.5 + 0.5 * dsigma) * (sx >= 0 ? 1 : -1), dMy = (0.5 - 0.5 * dsigma) * (sy >= 0 ? 1 : -1);
  const double scale = std::min(rx, ry);
  gd[0] = -scale * dMx / rx;
  gd[1] = -scale * dMy / ry;
  return scale * (1.0 - M) + buffer_;
}

namespace {
// M(a, b) = (a + b)/2 + sigma((a - b)/2) <= max(a, b) and its partials (see value()).
double smooth_max(double a, double b, double c, double& da, double& db) {
  const double z = 0.5 * (a - b), az = std::abs(z);
  double sigma = az, dsigma = z >= 0 ? 1.0 : -1.0;
  if (az < c) {
    sigma = z * z * (2 * c - az) / (c * c);
    dsigma = (z >= 0 ? 1.0 : -1.0) * (4 * c * az - 3 * z * z) / (c * c);
  }
  da = 0.5 + 0.5 * dsigma;
  db = 0.5 - 0.5 * dsigma;
  return 0.5 * (a + b) + sigma;
}
}  // namespace

double PairConstraint::value_inf3(const double* d, const WorkspaceMargin& m1, const WorkspaceMargin& m2,
                                  double* gd) const {
  // max(|dx|/rx, |dy|/ry, |dz|/rz) >= 1 through M(M(ax, ay), az), a C1 lower bound of the max.
  const double r[3] = {delta_ + m1.x + m2.x, delta_ + m1.y + m2.y, delta_ + m1.z + m2.z};
  double s[3], a[3];
  for (int c = 0; c < 3; ++c) {
    s[c] = d[c] / r[c];
    a[c] = std::abs(s[c]);
  }
  double d0, d1, e01, e2;
  const double m01 = smooth_max(a[0], a[1], corner_, d0, d1);
  const double M = smooth_max(m01, a[2], corner_, e01, e2);
  const double dM[3] = {e01 * d0, e01 * d1, e2};
  const double scale = std::min({r[0], r[1], r[2]});
  for (int c = 0; c < 3; ++c) gd[c] = -scale * dM[c] * (s[c] >= 0 ? 1 : -1) / r[c];
  return scale * (1.0 - M) + buffer_;
}

void PairConstraint::evaluate(const double* x, double* g, double* jac) const {
  const int na = a_->n(), nb = b_->n();
  const double *xa = x + support_[0], *xb = x + support_[na];
  const PairGeometry geo(*a_, *b_, xa, xb, jac != nullptr);
  double gd[kMaxWorkspaceDim] = {0, 0, 0};
  g[0] = value(geo.d, xa, xb, gd);
  if (jac) geo.chain(gd, na, nb, jac);
}

bool PairConstraint::hessian(const double* x, const double* w, double* H) const {
  const int na = a_->n(), nb = b_->n();
  const double *xa = x + support_[0], *xb = x + support_[na];
  // The nested 3-D smoothing of the max norm: the planner differences the Jacobian.
  if (a_->workspace.dim() == 3 && norm_ == Norm::Inf) return false;
  double Pa[2 * kMaxDual * kMaxDual], Pb[2 * kMaxDual * kMaxDual];
  if (!footprint_hessian(*a_, xa, Pa) || !footprint_hessian(*b_, xb, Pb)) return false;
  const PairGeometry geo(*a_, *b_, xa, xb, true);
  double gd[kMaxWorkspaceDim] = {0, 0, 0};
  value(geo.d, xa, xb, gd);
  double S[kMaxWorkspaceDim * kMaxWorkspaceDim] = {0, 0, 0, 0};
  if (norm_ == Norm::Two) {
    norm_curvature(geo.d, -w[0], S, geo.D);
  } else {
    // g = scale (1 - M): M is piecewise linear outside the smoothed corner; inside it the only
    // curvature is sigma''(z) along z's gradient v in d.
    const WorkspaceMargin m1 = ma_->at(xa), m2 = mb_->at(xb);
    const double rx = delta_ + m1.x + m2.x, ry = delta_ + m1.y + m2.y;
    const double sx = geo.d[0] / rx, sy = geo.d[1] / ry;
    const double z = 0.5 * (std::abs(sx) - std::abs(sy)), az = std::abs(z), c = corner_;
    if (az < c) {
      const double sigma2 = (4 * c - 6 * az) / (c * c);
      const double v[2] = {0.5 * (sx >= 0 ? 1 : -1) / rx, -0.5 * (sy >= 0 ? 1 : -1) / ry};
      const double k = -w[0] * std::min(rx, ry) * sigma2;
      S[0] = k * v[0] * v[0];
      S[1] = S[2] = k * v[0] * v[1];
      S[3] = k * v[1] * v[1];
    }
  }
  add_congruence(geo.Ja, na, geo.Jb, nb, S, H, geo.D);
  const double gw[2] = {w[0] * gd[0], w[0] * gd[1]};
  add_footprint_curvature(Pa, na, Pb, nb, gw, H);
  return true;
}

FormationConstraint::FormationConstraint(std::string name, const AgentSpec& a, int offset_a, const AgentSpec& b,
                                         int offset_b, double lambda, double mu,
                                         std::shared_ptr<const MarginTable> ma, std::shared_ptr<const MarginTable> mb,
                                         double buffer)
    : name_(std::move(name)), a_(&a), b_(&b), support_(range_support(offset_a, a.n(), offset_b, b.n())),
      lambda_(lambda), mu_(mu), ma_(std::move(ma)), mb_(std::move(mb)), buffer_(buffer) {}

void FormationConstraint::evaluate(const double* x, double* g, double* jac) const {
  const int na = a_->n(), nb = b_->n();
  const double *xa = x + support_[0], *xb = x + support_[na];
  const PairGeometry geo(*a_, *b_, xa, xb, jac != nullptr);
  const double slack = ma_->at(xa).two() + mb_->at(xb).two() + buffer_;
  const double len = geo.norm();
  g[0] = len - (lambda_ + mu_ - slack);
  g[1] = (lambda_ - mu_ + slack) - len;
  if (jac) {
    const double inv = len > 1e-12 ? 1.0 / len : 0.0;
    const double gd[kMaxWorkspaceDim] = {geo.d[0] * inv, geo.d[1] * inv, geo.d[2] * inv};
    const double gn[kMaxWorkspaceDim] = {-gd[0], -gd[1], -gd[2]};
    geo.chain(gd, na, nb, jac);
    geo.chain(gn, na, nb, jac + na + nb);
  }
}

bool FormationConstraint::hessian(const double* x, const double* w, double* H) const {
  const int na = a_->n(), nb = b_->n();
  const double *xa = x + support_[0], *xb = x + support_[na];
  double Pa[2 * kMaxDual * kMaxDual], Pb[2 * kMaxDual * kMaxDual];
  if (!footprint_hessian(*a_, xa, Pa) || !footprint_hessian(*b_, xb, Pb)) return false;
  const PairGeometry geo(*a_, *b_, xa, xb, true);
  // g_0 = |d| - ..., g_1 = ... - |d|: both rows through |d|, weighted w_0 - w_1.
  const double k = w[0] - w[1];
  double S[kMaxWorkspaceDim * kMaxWorkspaceDim];
  norm_curvature(geo.d, k, S, geo.D);
  add_congruence(geo.Ja, na, geo.Jb, nb, S, H, geo.D);
  const double len = geo.norm();
  const double inv = len > 1e-12 ? 1.0 / len : 0.0;
  const double gw[2] = {k * geo.d[0] * inv, k * geo.d[1] * inv};
  add_footprint_curvature(Pa, na, Pb, nb, gw, H);
  return true;
}

StateBoxConstraint::StateBoxConstraint(std::string name, int offset, const Box& box) : name_(std::move(name)) {
  for (int c = 0; c < box.dim(); ++c) {
    const bool lo = std::isfinite(box.lo[c]), hi = std::isfinite(box.hi[c]);
    if (!lo && !hi) continue;
    const int at = static_cast<int>(support_.size());
    support_.push_back(offset + c);
    if (lo) rows_.push_back({at, -1.0, box.lo[c]});
    if (hi) rows_.push_back({at, 1.0, box.hi[c]});
  }
}

void StateBoxConstraint::evaluate(const double* x, double* g, double* jac) const {
  const int w = static_cast<int>(support_.size());
  for (size_t r = 0; r < rows_.size(); ++r) {
    const Row& row = rows_[r];
    g[r] = row.sign * (x[support_[row.coord]] - row.bound);
    if (jac) {
      double* J = jac + r * w;
      for (int i = 0; i < w; ++i) J[i] = 0.0;
      J[row.coord] = row.sign;
    }
  }
}

}  // namespace marsyn::planning
