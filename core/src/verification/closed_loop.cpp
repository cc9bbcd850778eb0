#include "marsyn/core/verification/closed_loop.hpp"

#include <algorithm>
#include <stdexcept>

#include "marsyn/sampled_map.hpp"

namespace marsyn {

const char* to_string(DisturbanceMode m) {
  switch (m) {
    case DisturbanceMode::None: return "none";
    case DisturbanceMode::ConstantVertex: return "vertex";
    case DisturbanceMode::PaperConstant: return "paper";
    case DisturbanceMode::UniformRandom: return "uniform";
    case DisturbanceMode::VertexSwitching: return "switching";
    case DisturbanceMode::Adversarial: return "adversarial";
  }
  return "?";
}

DisturbanceMode parse_disturbance_mode(const std::string& s) {
  for (auto m : {DisturbanceMode::None, DisturbanceMode::ConstantVertex, DisturbanceMode::PaperConstant,
                 DisturbanceMode::UniformRandom, DisturbanceMode::VertexSwitching, DisturbanceMode::Adversarial})
    if (s == to_string(m)) return m;
  throw std::invalid_argument("unknown disturbance mode '" + s +
                              "'; expected one of: none, vertex, paper, uniform, switching, adversarial");
}

namespace {

// Per agent, per run: produces the disturbance for each sampling period.
class DisturbanceSource {
 public:
  DisturbanceSource(const Eigen::VectorXd& w, int agent, const Scenario& sc)
      : w_(w), mode_(sc.mode), rng_(sc.seed * 1000003ULL + static_cast<std::uint64_t>(agent) * 7919ULL + 17) {
    const int n = static_cast<int>(w.size());
    fixed_ = Eigen::VectorXd::Zero(n);
    if (mode_ == DisturbanceMode::PaperConstant) {
      // Variants: 0 alternating +W, -W, +W, ... over agents; 1 its negation; 2 all +W; 3 all -W.
      const bool even = agent % 2 == 0;
      const double sign = sc.variant == 0 ? (even ? 1.0 : -1.0)
                          : sc.variant == 1 ? (even ? -1.0 : 1.0)
                          : sc.variant == 2 ? 1.0
                                            : -1.0;
      fixed_ = sign * w_;
    } else if (mode_ == DisturbanceMode::ConstantVertex) {
      fixed_ = vertex();
    }
  }
  Eigen::VectorXd next() {
    switch (mode_) {
      case DisturbanceMode::None: return Eigen::VectorXd::Zero(w_.size());
      case DisturbanceMode::ConstantVertex:
      case DisturbanceMode::PaperConstant: return fixed_;
      case DisturbanceMode::UniformRandom: {
        Eigen::VectorXd d(w_.size());
        for (Eigen::Index i = 0; i < d.size(); ++i) d[i] = std::uniform_real_distribution<double>(-w_[i], w_[i])(rng_);
        return d;
      }
      case DisturbanceMode::VertexSwitching:
      case DisturbanceMode::Adversarial: return vertex();
    }
    return fixed_;
  }
  bool per_substep() const { return mode_ == DisturbanceMode::Adversarial; }

 private:
  Eigen::VectorXd vertex() {
    Eigen::VectorXd d(w_.size());
    for (Eigen::Index i = 0; i < d.size(); ++i) d[i] = (rng_() & 1u) ? w_[i] : -w_[i];
    return d;
  }
  Eigen::VectorXd w_, fixed_;
  DisturbanceMode mode_;
  std::mt19937_64 rng_;
};

// Nearest point of a convex polygon's boundary to p.
Eigen::Vector2d nearest_on_polygon(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  Eigen::Vector2d best = poly.front();
  double bd = 1e300;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d a = poly[i], b = poly[(i + 1) % poly.size()], ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const Eigen::Vector2d q = a + t * ab;
    if ((q - p).squaredNorm() < bd) {
      bd = (q - p).squaredNorm();
      best = q;
    }
  }
  return best;
}

// The adversary's vertex for agent i: on the coordinates its workspace point reads linearly,
// the sign that moves the point toward the nearest obstacle or other agent.
void adversarial_push(const Problem& pb, int i, const std::vector<Eigen::Vector2d>& pts, Eigen::VectorXd& w) {
  const AgentSpec& a = pb.agents[i];
  if (!a.workspace.linear()) return;
  Eigen::Vector2d target = pts[i];
  double bd = 1e300;
  for (const auto& o : pb.obstacles) {
    const Eigen::Vector2d q = nearest_on_polygon(o.vertices, pts[i]);
    if ((q - pts[i]).norm() < bd) {
      bd = (q - pts[i]).norm();
      target = q;
    }
  }
  if (pb.pairwise_collision)
    for (std::size_t j = 0; j < pts.size(); ++j)
      if (static_cast<int>(j) != i && (pts[j] - pts[i]).norm() < bd) {
        bd = (pts[j] - pts[i]).norm();
        target = pts[j];
      }
  if (bd >= 1e300) return;
  for (int c = 0; c < 2; ++c) {
    const int s = a.workspace.index[c];
    if (s < 0) continue;
    const double d = target[c] - pts[i][c];
    if (d != 0) w[s] = d > 0 ? a.tube.w[s] : -a.tube.w[s];
  }
}

}  // namespace

ClosedLoopRun simulate(const SimulationSetup& s, const Scenario& scenario) {
  const Problem& pb = *s.problem;
  const int N = static_cast<int>(pb.agents.size());
  if (static_cast<int>(s.nominal.size()) != N) throw std::invalid_argument("simulate: one nominal trajectory per agent");
  if (s.fine_substeps < 1) throw std::invalid_argument("simulate: fine_substeps must be positive");
  const bool closed = !s.controllers.empty();
  const int T = static_cast<int>(s.nominal.front().u.size());
  const int S = s.fine_substeps;

  ClosedLoopRun run;
  std::vector<Eigen::VectorXd> x(N), u(N), w(N);
  std::vector<DisturbanceSource> dist;
  for (int i = 0; i < N; ++i) {
    x[i] = pb.agents[i].x0;
    dist.emplace_back(pb.agents[i].tube.w, i, scenario);
  }
  Eigen::VectorXd prod(pb.product_state_dim());
  auto stack = [&] {
    int off = 0;
    for (int i = 0; i < N; ++i) {
      prod.segment(off, x[i].size()) = x[i];
      off += static_cast<int>(x[i].size());
    }
  };
  auto record = [&](int k) {
    stack();
    for (int i = 0; i < N; ++i) {
      const Eigen::VectorXd dev = (x[i] - s.nominal[i].x[k]).cwiseAbs().cwiseQuotient(pb.agents[i].tube.eps);
      run.max_tube_excess = std::max(run.max_tube_excess, dev.maxCoeff());
    }
    run.states.push_back(prod);
    if (s.keep_dense) {
      run.dense_t.push_back(k * pb.tau);
      run.dense_states.push_back(prod);
    }
  };
  std::vector<Eigen::Vector2d> pts(N);
  auto points = [&] {
    for (int i = 0; i < N; ++i) {
      double p[2];
      workspace_point<double>(*pb.agents[i].dynamics, pb.agents[i].workspace, x[i].data(), p);
      pts[i] = {p[0], p[1]};
    }
  };
  record(0);
  Eigen::VectorXd next;
  for (int k = 0; k < T; ++k) {
    // Zero-order hold: every agent's input is fixed at the sample from its own state.
    for (int i = 0; i < N; ++i) {
      const AgentSpec& a = pb.agents[i];
      u[i] = s.nominal[i].u[k];
      if (closed) {
        Eigen::VectorXd uc(a.m());
        const ControlStatus st = s.controllers[i]->input(x[i].data(), k, uc.data());
        if (st == ControlStatus::Ok) {
          u[i] = uc;
        } else if (run.outside_domain_agent < 0) {
          run.outside_domain_agent = i;
          run.outside_domain_step = k;
        }
      }
      w[i] = dist[i].next();
    }
    for (int sub = 0; sub < S; ++sub) {
      if (sub > 0 && (dist.front().per_substep())) {
        points();
        for (int i = 0; i < N; ++i) {
          w[i] = dist[i].next();
          adversarial_push(pb, i, pts, w[i]);
        }
      } else if (sub == 0 && dist.front().per_substep()) {
        points();
        for (int i = 0; i < N; ++i) adversarial_push(pb, i, pts, w[i]);
      }
      for (int i = 0; i < N; ++i) {
        const AgentSpec& a = pb.agents[i];
        next.resize(a.n());
        // One substep of h = tau / S: the same arithmetic as rk4_step over tau with S substeps.
        rk4_step<double>(*a.dynamics, x[i].data(), u[i].data(), w[i].data(), pb.tau, S, next.data(), 1);
        x[i] = next;
      }
      if (sub + 1 < S) {
        if (s.between || s.keep_dense) stack();
        if (s.keep_dense) {
          run.dense_t.push_back((k + static_cast<double>(sub + 1) / S) * pb.tau);
          run.dense_states.push_back(prod);
        }
        if (s.between) {
          const double before = run.between.min();
          if (s.between->accumulate(prod, run.between) && run.between.min() < before) {
            run.between_worst_t = (k + static_cast<double>(sub + 1) / S) * pb.tau;
            s.between->step(prod, &run.between_worst);  // named only for a new minimum
          }
        }
      }
    }
    record(k + 1);
  }
  return run;
}

}  // namespace marsyn
