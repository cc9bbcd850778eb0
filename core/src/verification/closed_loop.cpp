#include "marsyn/core/verification/closed_loop.hpp"

#include <algorithm>
#include <stdexcept>

#include "marsyn/core/verification/broad_phase.hpp"
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
      vertex(fixed_);
    }
  }
  // Writes the next disturbance into d (sized once by the caller: no allocation per step).
  void next(Eigen::VectorXd& d) {
    switch (mode_) {
      case DisturbanceMode::None: d.setZero(); return;
      case DisturbanceMode::ConstantVertex:
      case DisturbanceMode::PaperConstant: d = fixed_; return;
      case DisturbanceMode::UniformRandom:
        for (Eigen::Index i = 0; i < d.size(); ++i) d[i] = std::uniform_real_distribution<double>(-w_[i], w_[i])(rng_);
        return;
      case DisturbanceMode::VertexSwitching:
      case DisturbanceMode::Adversarial: vertex(d); return;
    }
  }

 private:
  void vertex(Eigen::VectorXd& d) {
    for (Eigen::Index i = 0; i < d.size(); ++i) d[i] = (rng_() & 1u) ? w_[i] : -w_[i];
  }
  Eigen::VectorXd w_, fixed_;
  DisturbanceMode mode_;
  std::mt19937_64 rng_;
};

// The adversary's target for agent i by a search over every obstacle and agent (the reference of
// BroadPhase::nearest_target, which must find the same one).
bool nearest_by_search(const Problem& pb, int i, const std::vector<Eigen::Vector2d>& pts, Eigen::Vector2d& target) {
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
  return bd < 1e300;
}

// The adversary's vertex for an agent at p: on the coordinates its workspace point reads
// linearly, the sign that moves the point toward the target.
void push_toward(const AgentSpec& a, const Eigen::Vector2d& p, const Eigen::Vector2d& target, Eigen::VectorXd& w) {
  for (int c = 0; c < 2; ++c) {
    const int s = a.workspace.index[c];
    if (s < 0) continue;
    const double d = target[c] - p[c];
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
  const bool adversary = scenario.mode == DisturbanceMode::Adversarial;

  ClosedLoopRun run;
  // Every buffer once per run: the loop below allocates nothing per step.
  std::vector<Eigen::VectorXd> x(N), u(N), uc(N), w(N), next(N);
  std::vector<DisturbanceSource> dist;
  dist.reserve(static_cast<size_t>(N));
  for (int i = 0; i < N; ++i) {
    const AgentSpec& a = pb.agents[i];
    x[i] = a.x0;
    uc[i].resize(a.m());
    next[i].resize(a.n());
    w[i].resize(a.tube.w.size());
    dist.emplace_back(a.tube.w, i, scenario);
  }
  Eigen::VectorXd prod(pb.product_state_dim());
  auto stack = [&] {
    int off = 0;
    for (int i = 0; i < N; ++i) {
      prod.segment(off, x[i].size()) = x[i];
      off += static_cast<int>(x[i].size());
    }
  };
  std::vector<Eigen::Vector2d> pts(N);
  BroadPhase broad(pb);
  const bool track_points = s.between || adversary || s.keep_dense;
  auto points = [&] {
    if (!track_points) return;
    for (int i = 0; i < N; ++i) workspace_point<double>(*pb.agents[i].dynamics, pb.agents[i].workspace, x[i].data(), pts[i].data());
    broad.update(pts);
  };
  // running = min(running, the spec at the current state) part by part; true, with the
  // requirement named, when the smallest part fell.
  auto fold = [&](StepMargins& running, std::string& name) {
    if (s.all_pairs) {
      std::string what;
      const StepMargins m = s.between->step(prod, &what);
      const double before = running.min();
      running = {std::min(running.obstacle, m.obstacle), std::min(running.collision, m.collision),
                 std::min(running.formation, m.formation), running.stage};
      if (!(running.min() < before)) return false;
      name = std::move(what);
      return true;
    }
    planning::Requirement q{planning::Requirement::Obstacle, -1, -1};
    if (!broad.accumulate(running, &q)) return false;
    name = q.name(pb);
    return true;
  };
  // The current state's own margins (a fresh fold: step()'s values) for the plots.
  auto keep_dense = [&](double t) {
    run.dense_t.push_back(t);
    run.dense_states.push_back(prod);
    StepMargins m;
    if (s.all_pairs && s.between) m = s.between->step(prod);
    else broad.accumulate(m, nullptr);
    run.dense_margins.push_back(m);
  };
  StepMargins at_samples;
  auto record = [&](int k) {
    stack();
    for (int i = 0; i < N; ++i) {
      const Eigen::VectorXd& nom = s.nominal[i].x[k];
      const Eigen::VectorXd& eps = pb.agents[i].tube.eps;
      for (Eigen::Index c = 0; c < x[i].size(); ++c)
        run.max_tube_excess = std::max(run.max_tube_excess, std::abs(x[i][c] - nom[c]) / eps[c]);
    }
    if (s.keep_states) run.states.push_back(prod);
    if (s.keep_dense) keep_dense(k * pb.tau);
    std::string name;
    // (A stage's margin may already be lower: the smaller one stays.)
    if (s.between && fold(at_samples, name) && at_samples.min() < run.sampled.min_margin) {
      run.sampled.min_margin = at_samples.min();
      run.sampled.worst = name + " at step " + std::to_string(k);
    }
    if (s.between) s.between->add_stages(k, prod, run.sampled);
  };
  points();
  record(0);
  for (int k = 0; k < T; ++k) {
    // Zero-order hold: every agent's input is fixed at the sample from its own state.
    for (int i = 0; i < N; ++i) {
      u[i] = s.nominal[i].u[k];
      if (closed) {
        const ControlStatus st = s.controllers[i]->input(x[i].data(), k, uc[i].data());
        if (st == ControlStatus::Ok) {
          u[i] = uc[i];
        } else if (run.outside_domain_agent < 0) {
          run.outside_domain_agent = i;
          run.outside_domain_step = k;
        }
      }
      dist[i].next(w[i]);
    }
    for (int sub = 0; sub < S; ++sub) {
      if (adversary)
        for (int i = 0; i < N; ++i) {
          const AgentSpec& a = pb.agents[i];
          if (sub > 0) dist[i].next(w[i]);
          if (!a.workspace.linear()) continue;
          Eigen::Vector2d target;
          if (s.all_pairs ? nearest_by_search(pb, i, pts, target) : broad.nearest_target(i, target))
            push_toward(a, pts[i], target, w[i]);
        }
      for (int i = 0; i < N; ++i) {
        // One substep of h = tau / S: the same arithmetic as rk4_step over tau with S substeps.
        rk4_step<double>(*pb.agents[i].dynamics, x[i].data(), u[i].data(), w[i].data(), pb.tau, S, next[i].data(), 1);
        x[i].swap(next[i]);
      }
      points();
      if (sub + 1 < S) {
        if (s.keep_dense || s.all_pairs) stack();
        if (s.keep_dense) keep_dense((k + static_cast<double>(sub + 1) / S) * pb.tau);
        if (s.between && fold(run.between, run.between_worst))
          run.between_worst_t = (k + static_cast<double>(sub + 1) / S) * pb.tau;
        // Mission stages dwelling over this period: the state stays in the region between the samples too.
        if (s.between && s.between->has_stages()) {
          if (!(s.keep_dense || s.all_pairs)) stack();
          std::string what;
          const double m = s.between->stage_between(k, prod, &what);
          if (m < run.between.stage) {
            const bool lowest = m < run.between.min();
            run.between.stage = m;
            if (lowest) {
              run.between_worst = what;
              run.between_worst_t = (k + static_cast<double>(sub + 1) / S) * pb.tau;
            }
          }
        }
      }
    }
    record(k + 1);
  }
  if (s.between) {
    s.between->add_goal(prod, run.sampled);
    run.sampled.satisfied = run.sampled.min_margin >= 0;
  }
  return run;
}

}  // namespace marsyn
