#include "marsyn/core/verification/closed_loop.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "marsyn/core/verification/broad_phase.hpp"
#include "marsyn/core/verification/lanes_rk4.hpp"
#include "marsyn/disturbance.hpp"
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
  // The run's start in the stated initial set x0 +- x0_radius (drawn after the constant
  // disturbance, from the same stream): x0 itself in the run without disturbance, a uniform point
  // where the disturbance is uniform, otherwise a vertex of the box (where a tube is widest).
  void start(const AgentSpec& a, Eigen::VectorXd& x) {
    x = a.x0;
    if (a.x0_radius.size() == 0 || mode_ == DisturbanceMode::None) return;
    for (int i = 0; i < a.n(); ++i) {
      const double r = a.x0_half(i);
      if (!(r > 0)) continue;
      x[i] += mode_ == DisturbanceMode::UniformRandom ? std::uniform_real_distribution<double>(-r, r)(rng_) : (bit() ? r : -r);
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
  // d[i] = bit ? w[i] : -w[i], as a flip of the sign bit (negation's own bits): a branch on a
  // random bit is mispredicted half the time, and the adversary draws a vertex at every substep.
  void vertex(Eigen::VectorXd& d) {
    const Eigen::Index n = d.size();
    if (bits_left_ < n) {
      for (Eigen::Index i = 0; i < n; ++i)
        d[i] = std::bit_cast<double>(std::bit_cast<std::uint64_t>(w_[i]) ^ (static_cast<std::uint64_t>(!bit()) << 63));
      return;
    }
    // The same bits, lowest first, without bit()'s refill test per coordinate.
    std::uint64_t b = bits_;
    for (Eigen::Index i = 0; i < n; ++i, b >>= 1)
      d[i] = std::bit_cast<double>(std::bit_cast<std::uint64_t>(w_[i]) ^ ((~b & 1u) << 63));
    bits_ = b;
    bits_left_ -= static_cast<int>(n);
  }
  // A vertex takes one random bit per coordinate: each 64-bit draw gives 64 of them (one draw
  // per bit was most of the adversary's random cost, which re-chooses at every substep).
  bool bit() {
    if (bits_left_ == 0) {
      bits_ = rng_();
      bits_left_ = 64;
    }
    const bool b = (bits_ & 1u) != 0;
    bits_ >>= 1;
    --bits_left_;
    return b;
  }
  Eigen::VectorXd w_, fixed_;
  DisturbanceMode mode_;
  std::mt19937_64 rng_;
  std::uint64_t bits_ = 0;
  int bits_left_ = 0;
};

// The adversary's vertex for an agent at p: on the coordinates its workspace point reads
// linearly, the sign that moves the point toward the target.
void push_toward(const AgentSpec& a, const planning::Point& p, const planning::Point& target, Eigen::VectorXd& w) {
  for (int c = 0; c < a.workspace.dim(); ++c) {
    const int s = a.workspace.index[c];
    if (s < 0) continue;
    const double d = target[c] - p[c];
    // (d > 0 ? w : -w) as a flip of the sign bit, negation's own bits: the direction to the
    // target is a coin toss between near-tied neighbours, and a branch on it is mispredicted.
    if (d != 0)
      w[s] = std::bit_cast<double>(std::bit_cast<std::uint64_t>(a.tube.w[s]) ^ (static_cast<std::uint64_t>(!(d > 0)) << 63));
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
    pts.resize(static_cast<size_t>(pb.body_count()));
    dist.reserve(static_cast<size_t>(n_agents));
    for (int i = 0; i < n_agents; ++i) {
      const AgentSpec& a = pb.agents[i];
      uc[i].resize(a.m());
      w[i].resize(a.tube.w.size());
      dist.emplace_back(a.tube.w, i, sc);
      dist.back().start(a, x[i]);
    }
    prod.resize(pb.product_state_dim());
  }
  ClosedLoopRun run;
  // Every buffer once per run: the loop below allocates nothing per step.
  std::vector<Eigen::VectorXd> x, u, uc, w;
  std::vector<DisturbanceSource> dist;
  Eigen::VectorXd prod;
  std::vector<planning::Point> pts;
  const std::vector<planning::Point>* now = &pts;  // the points at the current substep (pts or a window's)
  BroadPhase broad;  // keeps a pointer to pts: a Lane does not move once built
  std::vector<std::vector<planning::Point>> window;  // the points at the substeps between two samples
  StepMargins at_samples;
  bool adversary;
  // The requirements named last at the samples (with their step) and between them, as found: the
  // names are built once, when the run ends (the minima fall often early in a run).
  planning::Requirement sampled_q{planning::Requirement::Obstacle, -1, -1}, between_q = sampled_q;
  int sampled_k = -1;
  bool sampled_pending = false, between_pending = false;
};

}  // namespace

namespace {

// A batch of runs, stepped together: the runs' Lanes and the integrator's view of them.
class Batch {
 public:
  Batch(const SimulationSetup& s, std::span<const Scenario> scenarios)
      : s_(s), pb_(*s.problem), N_(static_cast<int>(pb_.agents.size())), B_(pb_.body_count()), S_(s.fine_substeps),
        L_(static_cast<int>(scenarios.size())), closed_(!s.controllers.empty()) {
    lanes_.reserve(static_cast<size_t>(L_));
    for (const Scenario& sc : scenarios) lanes_.emplace_back(pb_, sc);
    if (s.between)
      for (Lane& r : lanes_) r.broad.windows(&s.between->windows());
    any_adversary_ = std::any_of(lanes_.begin(), lanes_.end(), [](const Lane& r) { return r.adversary; });
    for (int l = 0; l < Lanes::kWidth; ++l)
      if (run_of(l).adversary) adversary_lanes_.push_back(l);
    track_points_ = s.between || any_adversary_ || s.keep_dense;
    // The dense check a period at a time (BroadPhase::window): the plain verification runs. The
    // kept runs keep every substep's margins and the reference checks every pair. Stages dwelling
    // over a period are measured as the substeps' points are written and folded substep by
    // substep after the requirements (between()'s order: the same minima and names).
    windowed_ = s.between && !s.keep_dense && !s.all_pairs && S_ > 1;
    if (windowed_) {
      for (Lane& r : lanes_)
        r.window.assign(static_cast<size_t>(S_ - 1), std::vector<planning::Point>(static_cast<size_t>(B_)));
      boxes_.resize(static_cast<size_t>(B_));
      lane_boxes_.resize(static_cast<size_t>(B_));
      if (s.between->has_stages()) {
        stage_m_.resize(static_cast<size_t>(L_ * (S_ - 1)));
        stage_v_.resize(stage_m_.size());
      }
    }
    // The integrator's view: per agent, its state, input and disturbance as Lanes (one lane per
    // run; lanes past L repeat run 0 so that they compute ordinary numbers, which are dropped).
    // Per body (an agent's first body, then the further ones), read from its agent's state.
    for (int b = 0; b < B_; ++b) {
      const Workspace& ws = pb_.body_spec(b).workspace;
      PointMap m;
      m.linear = ws.linear();
      m.dim = ws.dim();
      for (int c = 0; m.linear && c < m.dim; ++c) {
        m.index[c] = ws.index[static_cast<size_t>(c)];
        m.offset[c] = ws.offset[static_cast<size_t>(c)];
      }
      maps_.push_back(m);
    }
    rk_.reserve(static_cast<size_t>(N_));
    for (int i = 0; i < N_; ++i) rk_.emplace_back(*pb_.agents[i].dynamics);
    int n_max = 0;
    for (int i = 0; i < N_; ++i) n_max = std::max(n_max, pb_.agents[i].n());
    lane_x_.resize(static_cast<size_t>(n_max));
    X_.resize(N_);
    U_.resize(N_);
    W_.resize(N_);
    next_.resize(N_);
    for (int i = 0; i < N_; ++i) {
      X_[i].resize(static_cast<size_t>(pb_.agents[i].n()));
      next_[i].resize(X_[i].size());
      U_[i].resize(static_cast<size_t>(pb_.agents[i].m()));
      W_[i].resize(static_cast<size_t>(pb_.agents[i].tube.w.size()));
      bounds_.emplace_back(pb_.agents[i].tube);
    }
    for (int i = 0; i < N_; ++i) pack(X_[i], &Lane::x, i);
  }

  std::vector<ClosedLoopRun> run() {
    const int T = static_cast<int>(s_.nominal.front().u.size());
    for (Lane& r : lanes_) {
      points(r);
      record(r, 0);
    }
    for (int k = 0; k < T; ++k) {
      if (windowed_ && !stage_m_.empty()) dwelling(k);
      hold_inputs(k);
      for (int i = 0; i < N_; ++i) pack(U_[i], &Lane::u, i);
      for (int sub = 0; sub < S_; ++sub) {
        for (Lane& r : lanes_)
          if (r.adversary) push_adversary(r, sub);
        integrate(sub);
        if (windowed_ && sub + 1 < S_) {
          window_points(sub);
          continue;
        }
        for (Lane& r : lanes_) {
          points(r);
          if (sub + 1 < S_) between(r, k, sub);
        }
      }
      if (windowed_)
        for (int l = 0; l < L_; ++l) fold_window(l, k);
      for (Lane& r : lanes_) record(r, k + 1);
    }
    std::vector<ClosedLoopRun> out;
    out.reserve(lanes_.size());
    for (Lane& r : lanes_) {
      if (r.sampled_pending) r.run.sampled.worst = r.sampled_q.name(pb_) + " at step " + std::to_string(r.sampled_k);
      if (r.between_pending) r.run.between_worst = r.between_q.name(pb_);
      if (s_.between) {
        s_.between->add_goal(r.prod, r.run.sampled);
        r.run.sampled.satisfied = r.run.sampled.min_margin >= 0;
      }
      out.push_back(std::move(r.run));
    }
    return out;
  }

 private:
  Lane& run_of(int l) { return lanes_[static_cast<size_t>(l < L_ ? l : 0)]; }

  void pack(std::vector<Lanes>& to, std::vector<Eigen::VectorXd> Lane::*member, int i) {
    for (int l = 0; l < Lanes::kWidth; ++l) {
      const Eigen::VectorXd& v = (run_of(l).*member)[static_cast<size_t>(i)];
      for (Eigen::Index c = 0; c < v.size(); ++c) to[static_cast<size_t>(c)][l] = v[c];
    }
  }

  // The integrator's states into the lanes' own.
  void unpack() {
    for (int i = 0; i < N_; ++i)
      for (int l = 0; l < L_; ++l)
        for (std::size_t c = 0; c < X_[i].size(); ++c) lanes_[static_cast<size_t>(l)].x[i][static_cast<Eigen::Index>(c)] = X_[i][c][l];
  }

  void stack(Lane& r) const {
    int off = 0;
    for (int i = 0; i < N_; ++i) {
      r.prod.segment(off, r.x[i].size()) = r.x[i];
      off += static_cast<int>(r.x[i].size());
    }
  }

  void points(Lane& r) const {
    if (!track_points_) return;
    for (int b = 0; b < B_; ++b) {
      const AgentSpec& a = pb_.body_spec(b);
      workspace_point3<double>(*a.dynamics, a.workspace, r.x[static_cast<size_t>(pb_.body_agent(b))].data(),
                               r.pts[static_cast<size_t>(b)].data());
    }
    r.now = &r.pts;
    r.broad.update(r.pts);
  }

  // An agent's box over the current window in every lane, and the sum of its coordinates.
  struct WindowBox {
    Lanes xl, yl, xh, yh, sum;
  };

  // The points at substep sub into every lane's window (agents outer: each agent's map is read
  // once for all lanes); the adversary also needs them now. Read from the integrator's lanes: the
  // lanes' own states are unpacked at the sample only.
  void window_points(int sub) {
    // Each lane's points at this substep, looked up once (not per agent).
    planning::Point* to[Lanes::kWidth];
    for (int l = 0; l < L_; ++l) to[l] = lanes_[static_cast<size_t>(l)].window[static_cast<size_t>(sub)].data();
    constexpr double kInf = std::numeric_limits<double>::infinity();
    for (int i = 0; i < B_; ++i) {
      const std::vector<Lanes>& x = X_[static_cast<size_t>(pb_.body_agent(i))];
      const PointMap& m = maps_[static_cast<size_t>(i)];
      // The agent's box over the window so far and the sum of its coordinates (finite only when
      // every one is), all lanes at once: BroadPhase::window's, without reading the states again.
      WindowBox& box = boxes_[static_cast<size_t>(i)];
      if (sub == 0) box = {Lanes(kInf), Lanes(kInf), Lanes(-kInf), Lanes(-kInf), Lanes(0.0)};
      if (m.linear && m.dim >= 2) {
        // workspace_point3's formula, read in place: a coordinate is a column plus an offset, or
        // the offset (the same addition lane by lane).
        Lanes c[kMaxWorkspaceDim];
        c[2] = Lanes(0.0);
        for (int d = 0; d < m.dim; ++d)
          c[d] = m.index[d] >= 0 ? x[static_cast<size_t>(m.index[d])] + m.offset[d] : Lanes(m.offset[d]);
        add_to_box(box, c);
        for (int l = 0; l < L_; ++l) to[l][i] = {c[0][l], c[1][l], c[2][l]};
        continue;
      }
      for (int l = 0; l < L_; ++l) {
        for (std::size_t d = 0; d < x.size(); ++d) lane_x_[d] = x[d][l];
        planning::Point& q = to[l][i];
        workspace_point3<double>(*pb_.body_spec(i).dynamics, pb_.body_spec(i).workspace, lane_x_.data(), q.data());
        box.xl[l] = std::min(box.xl[l], q.x());
        box.yl[l] = std::min(box.yl[l], q.y());
        box.xh[l] = std::max(box.xh[l], q.x());
        box.yh[l] = std::max(box.yh[l], q.y());
        box.sum[l] += q.x() + q.y() + q.z();
      }
    }
    for (Lane& r : lanes_)
      if (r.adversary) {
        r.now = &r.window[static_cast<size_t>(sub)];
        r.broad.update(*r.now);
      }
    if (!active_.empty()) window_stages(sub, to);
  }

  // The stages dwelling over period k (SpecMonitor::stage_between's), and no depth found yet.
  void dwelling(int k) {
    active_.clear();
    const auto& visits = s_.between->visits();
    for (std::size_t v = 0; v < visits.size(); ++v)
      if (visits[v].dwells_over(k)) active_.push_back(static_cast<int>(v));
    std::fill(stage_m_.begin(), stage_m_.end(), 1e300);
    std::fill(stage_v_.begin(), stage_v_.end(), -1);
  }

  // Each lane's smallest depth at substep sub over the dwelling stages (stage_between's value and
  // visit, first of equals), from the integrator's states and the points just written.
  void window_stages(int sub, planning::Point* const* to) {
    const auto& visits = s_.between->visits();
    for (int v : active_) {
      const planning::StageVisit& visit = visits[static_cast<size_t>(v)];
      const std::vector<Lanes>& x = X_[static_cast<size_t>(visit.agent)];
      for (int l = 0; l < L_; ++l) {
        const std::size_t at = static_cast<size_t>(l * (S_ - 1) + sub);
        // A depth clearly above both this substep's smallest so far and the lane's stage minimum
        // (as the period began; it only falls until the fold) could neither be this substep's
        // smallest nor lower the minimum when folded: its exact value is not needed.
        if (s_.between->stage_clears(v, to[l][visit.agent], std::min(stage_m_[at], lanes_[static_cast<size_t>(l)].run.between.stage)))
          continue;
        for (std::size_t d = 0; d < x.size(); ++d) lane_x_[d] = x[d][l];
        const double m = s_.between->stage_depth(visit, lane_x_.data(), to[l][visit.agent]);
        if (m < stage_m_[at]) {
          stage_m_[at] = m;
          stage_v_[at] = v;
        }
      }
    }
  }

  // box = box extended by the points c (x, y, z per lane), two lanes per packed operation (SSE2).
  static void add_to_box(WindowBox& box, const Lanes* c) {
    using V = verification_detail::Double2;
    auto at = [](const Lanes& a, int j) {
      V v;
      std::memcpy(&v, a.v + 2 * j, sizeof v);
      return v;
    };
    auto put = [](Lanes& a, int j, const V& v) { std::memcpy(a.v + 2 * j, &v, sizeof v); };
    for (int j = 0; j < Lanes::kWidth / 2; ++j) {
      const V px = at(c[0], j), py = at(c[1], j), pz = at(c[2], j);
      const V xl = at(box.xl, j), yl = at(box.yl, j), xh = at(box.xh, j), yh = at(box.yh, j);
      put(box.xl, j, px < xl ? px : xl);
      put(box.yl, j, py < yl ? py : yl);
      put(box.xh, j, px > xh ? px : xh);
      put(box.yh, j, py > yh ? py : yh);
      put(box.sum, j, at(box.sum, j) + (px + py + pz));
    }
  }

  // The dense check of the substeps between samples k and k + 1, in order, over the window's
  // candidates: what between() finds at each of them.
  void fold_window(int l, int k) {
    Lane& r = lanes_[static_cast<size_t>(l)];
    bool finite = true;
    for (int i = 0; i < B_; ++i) {
      const WindowBox& b = boxes_[static_cast<size_t>(i)];
      lane_boxes_[static_cast<size_t>(i)] = {b.xl[l], b.yl[l], b.xh[l], b.yh[l]};
      // sum - sum is 0 only when every coordinate is finite (a sum that overflows on finite
      // points also fails, which only costs the skipping).
      finite = finite && b.sum[l] - b.sum[l] == 0;
    }
    r.broad.window(r.window, lane_boxes_, finite, r.run.between, {k, true});
    for (int sub = 0; sub + 1 < S_; ++sub) {
      const double t = (k + static_cast<double>(sub + 1) / S_) * pb_.tau;
      planning::Requirement q{planning::Requirement::Obstacle, -1, -1};
      if (r.broad.accumulate_window(sub, r.run.between, &q)) {
        r.between_q = q;
        r.between_pending = true;
        r.run.between_worst_t = t;
      }
      if (active_.empty()) continue;
      const std::size_t at = static_cast<size_t>(l * (S_ - 1) + sub);
      const double m = stage_m_[at];
      if (m < r.run.between.stage) {
        const bool lowest = m < r.run.between.min();
        r.run.between.stage = m;
        if (lowest) {
          r.run.between_worst = s_.between->visits()[static_cast<size_t>(stage_v_[at])].name;
          r.between_pending = false;
          r.run.between_worst_t = t;
        }
      }
    }
  }

  // running = min(running, the spec at the current state) part by part; true, with the
  // requirement named, when the smallest part fell.
  bool fold(Lane& r, StepMargins& running, std::string& name, planning::Moment when) const {
    if (s_.all_pairs) {
      std::string what;
      const StepMargins m = s_.between->step(r.prod, &what, when);
      const double before = running.min();
      running = {std::min(running.obstacle, m.obstacle), std::min(running.collision, m.collision),
                 std::min(running.formation, m.formation), running.stage};
      if (!(running.min() < before)) return false;
      name = std::move(what);
      return true;
    }
    planning::Requirement q{planning::Requirement::Obstacle, -1, -1};
    if (!r.broad.accumulate(running, &q, when)) return false;
    name = q.name(pb_);
    return true;
  }

  // The current state's own margins (a fresh fold: step()'s values) for the plots.
  void keep_dense(Lane& r, double t, planning::Moment when) const {
    r.run.dense_t.push_back(t);
    r.run.dense_states.push_back(r.prod);
    StepMargins m;
    if (s_.all_pairs && s_.between) m = s_.between->step(r.prod, nullptr, when);
    else r.broad.accumulate(m, nullptr, when);
    r.run.dense_margins.push_back(m);
  }

  void record(Lane& r, int k) const {
    stack(r);
    for (int i = 0; i < N_; ++i) {
      const Eigen::VectorXd& nom = s_.nominal[i].x[k];
      const Eigen::VectorXd& eps = pb_.agents[i].tube.eps;
      for (Eigen::Index c = 0; c < r.x[i].size(); ++c)
        r.run.max_tube_excess = std::max(r.run.max_tube_excess, std::abs(r.x[i][c] - nom[c]) / eps[c]);
    }
    if (s_.keep_states) r.run.states.push_back(r.prod);
    if (s_.keep_dense) keep_dense(r, k * pb_.tau, {k, false});
    if (!s_.between) return;
    // (A stage's margin may already be lower: the smaller one stays.)
    if (s_.all_pairs) {
      std::string name;
      if (fold(r, r.at_samples, name, {k, false}) && r.at_samples.min() < r.run.sampled.min_margin) {
        r.run.sampled.min_margin = r.at_samples.min();
        r.run.sampled.worst = name + " at step " + std::to_string(k);
      }
    } else {
      planning::Requirement q{planning::Requirement::Obstacle, -1, -1};
      if (r.broad.accumulate(r.at_samples, &q, {k, false}) && r.at_samples.min() < r.run.sampled.min_margin) {
        r.run.sampled.min_margin = r.at_samples.min();
        r.sampled_q = q;
        r.sampled_k = k;
        r.sampled_pending = true;
      }
    }
    const double before = r.run.sampled.min_margin;
    s_.between->add_stages(k, r.prod, r.run.sampled);
    if (r.run.sampled.min_margin < before) r.sampled_pending = false;  // a stage named itself
  }

  // Between samples k and k + 1, after substep sub: the dense check of one run.
  void between(Lane& r, int k, int sub) const {
    if (s_.keep_dense || s_.all_pairs) stack(r);
    const double t = (k + static_cast<double>(sub + 1) / S_) * pb_.tau;
    if (s_.keep_dense) keep_dense(r, t, {k, true});
    if (s_.between && fold(r, r.run.between, r.run.between_worst, {k, true})) r.run.between_worst_t = t;
    // Mission stages dwelling over this period: the state stays in the region between the samples too.
    if (s_.between && s_.between->has_stages()) {
      if (!(s_.keep_dense || s_.all_pairs)) stack(r);
      std::string what;
      const double m = s_.between->stage_between(k, r.prod, &what);
      if (m < r.run.between.stage) {
        const bool lowest = m < r.run.between.min();
        r.run.between.stage = m;
        if (lowest) {
          r.run.between_worst = what;
          r.run.between_worst_t = t;
        }
      }
    }
  }

  // Zero-order hold: every agent's input is fixed at the sample from its own state. Agents
  // outer: one controller's tables at step k serve the batch's runs one after the other, while
  // in cache (each run's draws and first failing agent are the same in either order).
  void hold_inputs(int k) {
    for (int i = 0; i < N_; ++i)
      for (Lane& r : lanes_) {
        r.u[i] = s_.nominal[i].u[k];
        if (closed_) {
          const ControlStatus st = s_.controllers[i]->input(r.x[i].data(), k, r.uc[i].data());
          if (st == ControlStatus::Ok) {
            r.u[i] = r.uc[i];
          } else if (r.run.outside_domain_agent < 0) {
            r.run.outside_domain_agent = i;
            r.run.outside_domain_step = k;
          }
        }
        r.dist[i].next(r.w[i]);
      }
  }

  // The adversary's disturbance for substep sub: toward the nearest obstacle or agent.
  void push_adversary(Lane& r, int sub) const {
    for (int i = 0; i < N_; ++i) {
      const AgentSpec& a = pb_.agents[i];
      if (sub > 0) r.dist[i].next(r.w[i]);
      if (!a.workspace.linear()) continue;
      planning::Point target;
      if (s_.all_pairs ? nearest_by_search(pb_, i, *r.now, target) : r.broad.nearest_target(i, target))
        push_toward(a, (*r.now)[static_cast<size_t>(i)], target, r.w[i]);
    }
  }

  // One substep of h = tau / S for every run at once: lane by lane the arithmetic of rk4_step
  // over tau with S substeps.
  void integrate(int sub) {
    // One stage of each agent of a group before the next (lanes_rk4.hpp): the agents' fields are
    // independent, so their latencies overlap; groups of a few agents keep the scratch in cache.
    constexpr int kGroup = 8;
    for (int g = 0; g < N_; g += kGroup) {
      const int end = std::min(N_, g + kGroup);
      for (int i = g; i < end; ++i) {
        // Within a period only the adversary's disturbances change, and a W that grows with the
        // state or input, which scales each run's draw at every substep.
        if (!bounds_[static_cast<size_t>(i)].constant()) {
          pack(W_[i], &Lane::w, i);
          scale_to_state(i);
        } else if (sub == 0) {
          pack(W_[i], &Lane::w, i);
        } else
          for (int l : adversary_lanes_) {
            const Eigen::VectorXd& w = run_of(l).w[static_cast<size_t>(i)];
            for (Eigen::Index c = 0; c < w.size(); ++c) W_[i][static_cast<size_t>(c)][l] = w[c];
          }
        rk_[static_cast<size_t>(i)].start(X_[i].data(), U_[i].data(), W_[i].data(), pb_.tau, S_);
      }
      for (int i = g; i < end; ++i) rk_[static_cast<size_t>(i)].second();
      for (int i = g; i < end; ++i) rk_[static_cast<size_t>(i)].third();
      for (int i = g; i < end; ++i) {
        rk_[static_cast<size_t>(i)].finish(next_[i].data());
        X_[i].swap(next_[i]);
      }
    }
    // The windowed check reads the substeps' points from the lanes (window_points).
    if (!windowed_ || sub + 1 == S_) unpack();
  }

  // The draws are made at W's largest value (TubeParams::w); where W(x, u) grows with the state
  // or input, each lane's draw is scaled to W at its state and input at the substep's start
  // (the adversary's vertex stays a vertex).
  void scale_to_state(int i) {
    const AgentSpec& a = pb_.agents[i];
    const int n = a.n(), m = a.m();
    double x[64], u[64], w[64], scratch[64];
    if (n > 64 || m > 64) throw std::logic_error("a state-dependent W for more than 64 states or inputs");
    for (int l = 0; l < Lanes::kWidth; ++l) {
      for (int c = 0; c < n; ++c) x[c] = X_[i][static_cast<size_t>(c)][l], w[c] = W_[i][static_cast<size_t>(c)][l];
      for (int j = 0; j < m; ++j) u[j] = U_[i][static_cast<size_t>(j)][l];
      bounds_[static_cast<size_t>(i)].scale(x, u, a.tube.w.data(), w, scratch);
      for (int c = 0; c < n; ++c) W_[i][static_cast<size_t>(c)][l] = w[c];
    }
  }

  const SimulationSetup& s_;
  const Problem& pb_;
  const int N_, B_, S_, L_;  // agents, bodies (body slots: planning::body_points), substeps, lanes
  const bool closed_;
  std::vector<Lane> lanes_;
  bool any_adversary_ = false, track_points_ = false, windowed_ = false;
  std::vector<int> adversary_lanes_;  // the integrator's lanes whose run is adversarial
  // Each agent's linear workspace map (Workspace's index and offset), read in the inner loop.
  struct PointMap {
    bool linear = true;
    int dim = 0;
    int index[kMaxWorkspaceDim] = {-1, -1, -1};
    double offset[kMaxWorkspaceDim] = {0, 0, 0};
  };
  std::vector<PointMap> maps_;
  std::vector<WindowBox> boxes_;  // per body
  // Windowed runs with stages: the visits dwelling over the current period, and per lane and
  // substep between two samples the smallest depth among them and its visit.
  std::vector<int> active_;
  std::vector<double> stage_m_;
  std::vector<int> stage_v_;
  std::vector<Eigen::Vector4d> lane_boxes_;  // one lane's boxes (x_lo, y_lo, x_hi, y_hi) per body
  std::vector<std::vector<Lanes>> X_, U_, W_, next_;
  std::vector<DisturbanceBound> bounds_;  // each agent's W(x, u)
  std::vector<verification_detail::LanesRk4> rk_;  // per agent
  std::vector<double> lane_x_;                     // one lane's state of one agent
};

}  // namespace

std::vector<ClosedLoopRun> simulate(const SimulationSetup& s, std::span<const Scenario> scenarios) {
  const int N = static_cast<int>(s.problem->agents.size());
  if (static_cast<int>(s.nominal.size()) != N) throw std::invalid_argument("simulate: one nominal trajectory per agent");
  if (s.fine_substeps < 1) throw std::invalid_argument("simulate: fine_substeps must be positive");
  if (scenarios.empty() || scenarios.size() > static_cast<size_t>(Lanes::kWidth))
    throw std::invalid_argument("simulate: 1 to " + std::to_string(Lanes::kWidth) + " scenarios at once");
  return Batch(s, scenarios).run();
}

ClosedLoopRun simulate(const SimulationSetup& s, const Scenario& scenario) {
  return std::move(simulate(s, std::span<const Scenario>(&scenario, 1)).front());
}

}  // namespace marsyn
