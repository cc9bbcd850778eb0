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

namespace {

// One run of a batch: its agents' states, inputs and disturbances, its own broad phase over its
// own points, and what it has found so far.
struct Lane {
  Lane(const Problem& pb, const Scenario& sc) : broad(pb), adversary(sc.mode == DisturbanceMode::Adversarial) {
    const int n_agents = static_cast<int>(pb.agents.size());
    x.resize(n_agents);
    u.resize(n_agents);
    uc.resize(n_agents);
    w.resize(n_agents);
    pts.resize(n_agents);
    dist.reserve(static_cast<size_t>(n_agents));
    for (int i = 0; i < n_agents; ++i) {
      const AgentSpec& a = pb.agents[i];
      x[i] = a.x0;
      uc[i].resize(a.m());
      w[i].resize(a.tube.w.size());
      dist.emplace_back(a.tube.w, i, sc);
    }
    prod.resize(pb.product_state_dim());
  }
  ClosedLoopRun run;
  // Every buffer once per run: the loop below allocates nothing per step.
  std::vector<Eigen::VectorXd> x, u, uc, w;
  std::vector<DisturbanceSource> dist;
  Eigen::VectorXd prod;
  std::vector<Eigen::Vector2d> pts;
  BroadPhase broad;  // keeps a pointer to pts: a Lane does not move once built
  StepMargins at_samples;
  bool adversary;
};

}  // namespace

std::vector<ClosedLoopRun> simulate(const SimulationSetup& s, std::span<const Scenario> scenarios) {
  const Problem& pb = *s.problem;
  const int N = static_cast<int>(pb.agents.size());
  if (static_cast<int>(s.nominal.size()) != N) throw std::invalid_argument("simulate: one nominal trajectory per agent");
  if (s.fine_substeps < 1) throw std::invalid_argument("simulate: fine_substeps must be positive");
  if (scenarios.empty() || scenarios.size() > static_cast<size_t>(Lanes::kWidth))
    throw std::invalid_argument("simulate: 1 to " + std::to_string(Lanes::kWidth) + " scenarios at once");
  const bool closed = !s.controllers.empty();
  const int T = static_cast<int>(s.nominal.front().u.size());
  const int S = s.fine_substeps;
  const int L = static_cast<int>(scenarios.size());

  std::vector<Lane> lanes;
  lanes.reserve(static_cast<size_t>(L));
  for (const Scenario& sc : scenarios) lanes.emplace_back(pb, sc);
  const bool any_adversary = std::any_of(lanes.begin(), lanes.end(), [](const Lane& r) { return r.adversary; });
  const bool track_points = s.between || any_adversary || s.keep_dense;

  // The integrator's view: per agent, its state, input and disturbance as Lanes (one lane per
  // run; lanes past L repeat run 0 so that they compute ordinary numbers, which are dropped).
  std::vector<std::vector<Lanes>> X(N), U(N), W(N), next(N);
  for (int i = 0; i < N; ++i) {
    X[i].resize(static_cast<size_t>(pb.agents[i].n()));
    next[i].resize(X[i].size());
    U[i].resize(static_cast<size_t>(pb.agents[i].m()));
    W[i].resize(static_cast<size_t>(pb.agents[i].tube.w.size()));
  }
  auto run_of = [&](int l) -> Lane& { return lanes[static_cast<size_t>(l < L ? l : 0)]; };
  auto pack = [&](std::vector<Lanes>& to, auto member, int i) {
    for (int l = 0; l < Lanes::kWidth; ++l) {
      const Eigen::VectorXd& v = (run_of(l).*member)[static_cast<size_t>(i)];
      for (Eigen::Index c = 0; c < v.size(); ++c) to[static_cast<size_t>(c)][l] = v[c];
    }
  };
  for (int i = 0; i < N; ++i) pack(X[i], &Lane::x, i);

  auto stack = [&](Lane& r) {
    int off = 0;
    for (int i = 0; i < N; ++i) {
      r.prod.segment(off, r.x[i].size()) = r.x[i];
      off += static_cast<int>(r.x[i].size());
    }
  };
  auto points = [&](Lane& r) {
    if (!track_points) return;
    for (int i = 0; i < N; ++i) workspace_point<double>(*pb.agents[i].dynamics, pb.agents[i].workspace, r.x[i].data(), r.pts[i].data());
    r.broad.update(r.pts);
  };
  // running = min(running, the spec at the current state) part by part; true, with the
  // requirement named, when the smallest part fell.
  auto fold = [&](Lane& r, StepMargins& running, std::string& name) {
    if (s.all_pairs) {
      std::string what;
      const StepMargins m = s.between->step(r.prod, &what);
      const double before = running.min();
      running = {std::min(running.obstacle, m.obstacle), std::min(running.collision, m.collision),
                 std::min(running.formation, m.formation), running.stage};
      if (!(running.min() < before)) return false;
      name = std::move(what);
      return true;
    }
    planning::Requirement q{planning::Requirement::Obstacle, -1, -1};
    if (!r.broad.accumulate(running, &q)) return false;
    name = q.name(pb);
    return true;
  };
  // The current state's own margins (a fresh fold: step()'s values) for the plots.
  auto keep_dense = [&](Lane& r, double t) {
    r.run.dense_t.push_back(t);
    r.run.dense_states.push_back(r.prod);
    StepMargins m;
    if (s.all_pairs && s.between) m = s.between->step(r.prod);
    else r.broad.accumulate(m, nullptr);
    r.run.dense_margins.push_back(m);
  };
  auto record = [&](Lane& r, int k) {
    stack(r);
    for (int i = 0; i < N; ++i) {
      const Eigen::VectorXd& nom = s.nominal[i].x[k];
      const Eigen::VectorXd& eps = pb.agents[i].tube.eps;
      for (Eigen::Index c = 0; c < r.x[i].size(); ++c)
        r.run.max_tube_excess = std::max(r.run.max_tube_excess, std::abs(r.x[i][c] - nom[c]) / eps[c]);
    }
    if (s.keep_states) r.run.states.push_back(r.prod);
    if (s.keep_dense) keep_dense(r, k * pb.tau);
    std::string name;
    // (A stage's margin may already be lower: the smaller one stays.)
    if (s.between && fold(r, r.at_samples, name) && r.at_samples.min() < r.run.sampled.min_margin) {
      r.run.sampled.min_margin = r.at_samples.min();
      r.run.sampled.worst = name + " at step " + std::to_string(k);
    }
    if (s.between) s.between->add_stages(k, r.prod, r.run.sampled);
  };
  // Between samples k and k + 1, after substep sub: the dense check of one run.
  auto between = [&](Lane& r, int k, int sub) {
    if (s.keep_dense || s.all_pairs) stack(r);
    const double t = (k + static_cast<double>(sub + 1) / S) * pb.tau;
    if (s.keep_dense) keep_dense(r, t);
    if (s.between && fold(r, r.run.between, r.run.between_worst)) r.run.between_worst_t = t;
    // Mission stages dwelling over this period: the state stays in the region between the samples too.
    if (s.between && s.between->has_stages()) {
      if (!(s.keep_dense || s.all_pairs)) stack(r);
      std::string what;
      const double m = s.between->stage_between(k, r.prod, &what);
      if (m < r.run.between.stage) {
        const bool lowest = m < r.run.between.min();
        r.run.between.stage = m;
        if (lowest) {
          r.run.between_worst = what;
          r.run.between_worst_t = t;
        }
      }
    }
  };

  for (Lane& r : lanes) {
    points(r);
    record(r, 0);
  }
  for (int k = 0; k < T; ++k) {
    // Zero-order hold: every agent's input is fixed at the sample from its own state.
    for (Lane& r : lanes)
      for (int i = 0; i < N; ++i) {
        r.u[i] = s.nominal[i].u[k];
        if (closed) {
          const ControlStatus st = s.controllers[i]->input(r.x[i].data(), k, r.uc[i].data());
          if (st == ControlStatus::Ok) {
            r.u[i] = r.uc[i];
          } else if (r.run.outside_domain_agent < 0) {
            r.run.outside_domain_agent = i;
            r.run.outside_domain_step = k;
          }
        }
        r.dist[i].next(r.w[i]);
      }
    for (int i = 0; i < N; ++i) pack(U[i], &Lane::u, i);
    for (int sub = 0; sub < S; ++sub) {
      for (Lane& r : lanes) {
        if (!r.adversary) continue;
        for (int i = 0; i < N; ++i) {
          const AgentSpec& a = pb.agents[i];
          if (sub > 0) r.dist[i].next(r.w[i]);
          if (!a.workspace.linear()) continue;
          Eigen::Vector2d target;
          if (s.all_pairs ? nearest_by_search(pb, i, r.pts, target) : r.broad.nearest_target(i, target))
            push_toward(a, r.pts[i], target, r.w[i]);
        }
      }
      for (int i = 0; i < N; ++i) {
        // One substep of h = tau / S for every run at once: lane by lane the arithmetic of
        // rk4_step over tau with S substeps.
        if (sub == 0 || any_adversary) pack(W[i], &Lane::w, i);
        rk4_step_lanes(*pb.agents[i].dynamics, X[i].data(), U[i].data(), W[i].data(), pb.tau, S, next[i].data(), 1);
        X[i].swap(next[i]);
        for (int l = 0; l < L; ++l)
          for (std::size_t c = 0; c < X[i].size(); ++c) lanes[static_cast<size_t>(l)].x[i][static_cast<Eigen::Index>(c)] = X[i][c][l];
      }
      for (Lane& r : lanes) {
        points(r);
        if (sub + 1 < S) between(r, k, sub);
      }
    }
    for (Lane& r : lanes) record(r, k + 1);
  }
  std::vector<ClosedLoopRun> out;
  out.reserve(lanes.size());
  for (Lane& r : lanes) {
    if (s.between) {
      s.between->add_goal(r.prod, r.run.sampled);
      r.run.sampled.satisfied = r.run.sampled.min_margin >= 0;
    }
    out.push_back(std::move(r.run));
  }
  return out;
}

ClosedLoopRun simulate(const SimulationSetup& s, const Scenario& scenario) {
  return std::move(simulate(s, std::span<const Scenario>(&scenario, 1)).front());
}

}  // namespace marsyn
