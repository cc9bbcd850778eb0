#include "marsyn/core/closed_loop.hpp"

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
  }
  return "?";
}

DisturbanceMode parse_disturbance_mode(const std::string& s) {
  for (auto m : {DisturbanceMode::None, DisturbanceMode::ConstantVertex, DisturbanceMode::PaperConstant,
                 DisturbanceMode::UniformRandom, DisturbanceMode::VertexSwitching})
    if (s == to_string(m)) return m;
  throw std::invalid_argument("unknown disturbance mode '" + s +
                              "'; expected one of: none, vertex, paper, uniform, switching");
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
      case DisturbanceMode::VertexSwitching: return vertex();
    }
    return fixed_;
  }

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

}  // namespace

ClosedLoopRun simulate(const SimulationSetup& s, const Scenario& scenario) {
  const Problem& pb = *s.problem;
  const int N = static_cast<int>(pb.agents.size());
  if (static_cast<int>(s.nominal.size()) != N) throw std::invalid_argument("simulate: one nominal trajectory per agent");
  const bool closed = !s.controllers.empty();
  const int T = static_cast<int>(s.nominal.front().u.size());

  ClosedLoopRun run;
  std::vector<Eigen::VectorXd> x(N);
  std::vector<DisturbanceSource> dist;
  for (int i = 0; i < N; ++i) {
    x[i] = pb.agents[i].x0;
    dist.emplace_back(pb.agents[i].w, i, scenario);
  }
  auto record = [&](int k) {
    Eigen::VectorXd prod(pb.product_state_dim());
    int off = 0;
    for (int i = 0; i < N; ++i) {
      prod.segment(off, x[i].size()) = x[i];
      off += static_cast<int>(x[i].size());
      const Eigen::VectorXd dev = (x[i] - s.nominal[i].x[k]).cwiseAbs().cwiseQuotient(pb.agents[i].eps);
      run.max_tube_excess = std::max(run.max_tube_excess, dev.maxCoeff());
    }
    run.states.push_back(prod);
  };
  record(0);
  for (int k = 0; k < T; ++k) {
    for (int i = 0; i < N; ++i) {
      const AgentSpec& a = pb.agents[i];
      Eigen::VectorXd u = s.nominal[i].u[k];
      if (closed) {
        Eigen::VectorXd uc(a.m());
        const ControlStatus st = s.controllers[i]->input(x[i].data(), k, uc.data());
        if (st == ControlStatus::Ok) {
          u = uc;
        } else if (run.outside_domain_agent < 0) {
          run.outside_domain_agent = i;
          run.outside_domain_step = k;
        }
      }
      const Eigen::VectorXd w = dist[i].next();
      Eigen::VectorXd next(a.n());
      rk4_step<double>(*a.dynamics, x[i].data(), u.data(), w.data(), pb.tau, s.fine_substeps, next.data());
      x[i] = next;
    }
    record(k + 1);
  }
  return run;
}

}  // namespace marsyn
