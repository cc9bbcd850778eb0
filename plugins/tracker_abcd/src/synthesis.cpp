#include "synthesis.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <numeric>

#include "marsyn/number_text.hpp"
#include "marsyn/stopwatch.hpp"
#include "grid_fields.hpp"
#include "period_enclosure.hpp"
#include "split_sweep.hpp"
#include "synthesis_setup.hpp"
#include "tube.hpp"

namespace marsyn::abcd {
namespace {

// Narrows R (rows, invariant coordinates free) to the rows whose cover of the entry range
// [lo, hi] lies inside the next tube box; false if the non-invariant cover already leaves it or
// no row remains.
bool rows_inside(const std::vector<bool>& inv, const std::int64_t* cidx, const std::int16_t* lo, const std::int16_t* hi,
                 const IndexBox& next, IndexBox& R) {
  for (int i = 0; i < R.n; ++i) {
    if (inv[i]) {
      R.lo[i] = std::max(R.lo[i], next.lo[i] - lo[i]);
      R.hi[i] = std::min(R.hi[i], next.hi[i] - hi[i]);
      if (R.lo[i] > R.hi[i]) return false;
    } else if (cidx[i] + lo[i] < next.lo[i] || cidx[i] + hi[i] > next.hi[i]) {
      return false;
    }
  }
  return true;
}

// "" or why the problem is not one this synthesis takes; builds the grids.
std::string check_track(const TrackingProblem& p, UniformGrid& g, InputGrid& ug) {
  if (std::string e = check_dynamics(p.dynamics.get()); !e.empty()) return e;
  const int n = p.dynamics->state_dim(), m = p.dynamics->input_dim();
  if (p.nominal.x.size() < 2) return "the nominal trajectory needs at least two states";
  for (const auto& x : p.nominal.x)
    if (x.size() != n || !x.allFinite()) return "a nominal state has the wrong dimension or is not finite";
  const Eigen::VectorXd eta_x = p.fields.value(kEtaX), eta_u = p.fields.value(kEtaU);  // the agent's grid
  if (std::string e = check_vectors({{&p.tube.eps, n, "eps", true},
                                     {&eta_x, n, "eta_x", true},
                                     {&p.tube.w, n, "W", false},
                                     {&eta_u, m, "eta_u", true}});
      !e.empty())
    return e;
  if (p.initial_radius.size() != 0 && p.initial_radius.size() != n)
    return "the stated initial set has " + std::to_string(p.initial_radius.size()) + " half-widths, expected " + std::to_string(n);
  if (p.state_bounds.lo.size() != n) return "state bounds have the wrong dimension";
  if (p.input_bounds.lo.size() != m || p.input_bounds.hi.size() != m) return "input bounds have the wrong dimension";
  if (!(p.tau > 0)) return "tau must be positive";
  return make_grids(p.state_bounds.lo, eta_x, p.input_bounds, eta_u, g, ug);
}

// The tube's boxes for steps 0..T and the tables' offsets for steps 0..T-1, with their counts;
// returns the number of table entries.
std::int64_t lay_out_tube(const TrackingProblem& p, const UniformGrid& g, const InputGrid& ug, ControllerData& d,
                          TrackerStats& st, GridFigures& fig) {
  const int T = static_cast<int>(p.nominal.x.size()) - 1;
  std::int64_t total = 0;
  for (int k = 0; k <= T; ++k) {
    d.boxes.push_back(tube_box(g, p.nominal.x[k].data(), p.tube.eps.data()));
    const std::int64_t cells = d.boxes.back().size();
    fig.tube_cells += cells;
    if (k < T) {
      d.offsets.push_back(total);
      total += cells;
      st.state_input_pairs += static_cast<double>(cells) * static_cast<double>(ug.size());
    }
  }
  return total;
}

// Inputs by closeness to the nominal input of step k (in units of eta_u), ties by index.
void order_inputs(const TrackingProblem& p, int k, const InputGrid& ug, const std::vector<double>& uval,
                  std::vector<double>& dist, std::vector<std::int64_t>& order) {
  const int m = static_cast<int>(ug.lo().size());
  const bool has_nominal = static_cast<int>(p.nominal.u.size()) > k && p.nominal.u[k].size() == m;
  for (std::int64_t j = 0; j < ug.size(); ++j) {
    double s = 0;
    for (int c = 0; c < m; ++c) {
      const double ref = has_nominal ? p.nominal.u[k][c] : 0.5 * (ug.lo()[c] + ug.hi()[c]);
      const double z = (uval[static_cast<size_t>(j * m + c)] - ref) / ug.eta()[c];
      s += z * z;
    }
    dist[static_cast<size_t>(j)] = s;
  }
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::int64_t a, std::int64_t b) {
    return dist[static_cast<size_t>(a)] < dist[static_cast<size_t>(b)];
  });
}

// One backward step, as every thread reads it. Columns: fixed non-invariant indices; rows: the
// invariant indices. All cells of a column share one relative successor box per input, and its
// cover is the row's index plus a constant offset, so the rows whose cover stays inside the
// next tube form a box.
struct Step {
  int n;
  const std::vector<bool>& inv;
  const IndexBox& bk;  // this step's tube box
  const IndexBox& bn;  // the next step's
  const WinningSet& ws;
  IndexBox colbox, rowbox;
  std::int64_t columns, rows;
  std::int64_t off;  // this step's table in ControllerData::inputs
  bool keep_rejects;
  bool prefilter;

  Step(const std::vector<bool>& inv_, const IndexBox& bk_, const IndexBox& bn_, const WinningSet& ws_, std::int64_t off_,
       std::int64_t inputs, bool prefilter_)
      : n(bk_.n), inv(inv_), bk(bk_), bn(bn_), ws(ws_), colbox(bk_), rowbox(bk_), off(off_), prefilter(prefilter_) {
    for (int i = 0; i < n; ++i) {
      if (inv[i]) colbox.hi[i] = colbox.lo[i];
      else rowbox.lo[i] = rowbox.hi[i] = bk.lo[i];
    }
    columns = colbox.size();
    rows = rowbox.size();
    // Keeping rejected centre probes in the cache pays when the (column, input) pairs are few
    // (they recur every step); with many, the memory is not worth it.
    keep_rejects = static_cast<double>(columns) * static_cast<double>(inputs) <= 262144.0;
  }

  bool in_box(const IndexBox& R, const std::int64_t* ri) const {
    for (int i = 0; i < n; ++i)
      if (inv[i] && (ri[i] < R.lo[i] || ri[i] > R.hi[i])) return false;
    return true;
  }
};

// One column of a step: its indices and its pending rows, as row index boxes' multi-indices
// (compacted as rows are won).
struct Column {
  std::int64_t cidx[kMaxDim];
  std::vector<std::int64_t> pend;
  std::vector<std::int64_t> pidx;  // rows x n multi-indices

  void reset(const Step& s) {
    pend.resize(static_cast<size_t>(s.rows));
    pidx.resize(static_cast<size_t>(s.rows * s.n));
    for (std::int64_t row = 0; row < s.rows; ++row) {
      pend[static_cast<size_t>(row)] = row;
      s.rowbox.unlinear(row, &pidx[static_cast<size_t>(row * s.n)]);
      for (int i = 0; i < s.n; ++i)
        if (!s.inv[i]) pidx[static_cast<size_t>(row * s.n + i)] = cidx[i];
    }
  }
  const std::int64_t* row(size_t q, int n) const { return &pidx[static_cast<size_t>(pend[q] * n)]; }
};

// Whether the probes reject input j for the column: the rows R narrowed by the probe hull's
// cover leave no pending row whose whole hull cover is winning. A larger hull only narrows R
// and grows the covers, so a rejection by part of the probes is a rejection by all of them.
// `ep` may move from `fresh` into the table.
bool prefilter_rejects(const Step& s, SuccessorTable& tab, const Column& c, std::int64_t j, RelBox*& ep, RelBox& fresh,
                       IndexBox& R) {
  auto rejects = [&](const RelBox& e, IndexBox& Rr) {
    if (!rows_inside(s.inv, c.cidx, e.hlo, e.hhi, s.bn, Rr)) return true;
    IndexBox cov;
    for (size_t q = 0; q < c.pend.size(); ++q) {
      const std::int64_t* ri = c.row(q, s.n);
      if (!s.in_box(Rr, ri)) continue;
      tab.cover(e.hlo, e.hhi, ri, cov);
      if (s.ws.all_winning(cov)) return false;
    }
    return true;
  };
  // Stage 1: the centre alone (cheap rejection).
  tab.probe(*ep, c.cidx, j, 1);
  if (ep->has_hull && rejects(*ep, R)) return true;
  // Stage 2: the corners. Entries are stored once the centre probe passes (or always,
  // keep_rejects). Partial hulls (after 2, 4, 8 corners) are tried on a copy of R, so only a
  // rejection can end the stage early; the decision to go on to the box is always taken with
  // the full hull, exactly as without the early exit.
  if (ep == &fresh) ep = &tab.insert(c.cidx, j, fresh);
  RelBox& e = *ep;
  const int total = tab.total_probes();
  for (int upto : {3, 5, 9}) {
    if (upto >= total || e.probed >= upto) continue;
    tab.probe(e, c.cidx, j, upto);
    IndexBox Rt = R;
    if (e.has_hull && rejects(e, Rt)) return true;
  }
  tab.probe(e, c.cidx, j, total);
  return e.has_hull && rejects(e, R);
}

// Gives the column's pending rows the first input, in `order`, whose successor box's cover is
// winning; the rows no input wins stay kLosing.
void sweep_column(const Step& s, SuccessorTable& tab, Column& c, const std::vector<std::int64_t>& order,
                  std::vector<std::uint16_t>& inputs) {
  for (std::int64_t j : order) {
    if (c.pend.empty()) break;
    RelBox fresh;
    RelBox* ep = s.keep_rejects ? &tab.entry(c.cidx, j) : tab.find(c.cidx, j);
    if (!ep) ep = &fresh;
    IndexBox R = s.rowbox;  // rows that may still win with input j
    if (s.prefilter && prefilter_rejects(s, tab, c, j, ep, fresh, R)) continue;
    if (ep == &fresh) ep = &tab.insert(c.cidx, j, fresh);
    RelBox& e = *ep;
    tab.box(e, c.cidx, j);
    if (!e.ok) continue;
    if (!rows_inside(s.inv, c.cidx, e.lo, e.hi, s.bn, R)) continue;
    IndexBox cov;
    size_t keep = 0;
    for (size_t q = 0; q < c.pend.size(); ++q) {
      const std::int64_t* ri = c.row(q, s.n);
      bool won = false;
      if (s.in_box(R, ri)) {
        tab.cover(e, ri, cov);
        if (s.ws.all_winning(cov)) {
          inputs[static_cast<size_t>(s.off + s.bk.linear(ri))] = static_cast<std::uint16_t>(j);
          won = true;
        }
      }
      if (!won) c.pend[keep++] = c.pend[q];
    }
    c.pend.resize(keep);
  }
}

// Columns a thread sweeps between two polls of the stop request: a poll is a clock read, a column
// from microseconds (2 states) to tens of milliseconds (6 states, fine grids).
constexpr std::int64_t kStopEvery = 16;

// The backward sweep from step T-1; returns the last step swept: -1 when complete, else the
// step whose winning set is empty, or at which the stop request (o.stop) ended the sweep
// (`stopped` set).
int backward_sweep(const TrackingProblem& p, const Options& o, const InputGrid& ug,
                   const std::vector<bool>& inv, const SweepSplit& split,
                   std::vector<std::unique_ptr<SuccessorTable>>& tables, ControllerData& d, GridFigures& fig,
                   bool& stopped) {
  const int T = static_cast<int>(p.nominal.x.size()) - 1;
  const int m = static_cast<int>(ug.lo().size());
  const int threads = static_cast<int>(tables.size());
  std::vector<std::uint8_t> win(static_cast<size_t>(d.boxes[T].size()), 1);
  fig.winning_cells_per_step[T] = d.boxes[T].size();
  std::vector<double> uval(static_cast<size_t>(ug.size() * m));
  for (std::int64_t j = 0; j < ug.size(); ++j) ug.value(j, &uval[static_cast<size_t>(j * m)]);
  std::vector<std::int64_t> order(static_cast<size_t>(ug.size()));
  std::vector<double> dist(order.size());

  // Ranks sharing the sweep exchange every step's winning set: none may leave it alone.
  const bool stoppable = o.stop && !split.split();
  std::atomic<bool> stop{false};
  int k = T - 1;
  for (; k >= 0; --k) {
    const WinningSet ws(d.boxes[k + 1], win);
    order_inputs(p, k, ug, uval, dist, order);
    const Step s(inv, d.boxes[k], d.boxes[k + 1], ws, d.offsets[k], ug.size(), o.prefilter);
    run_threads(threads, [&](int t) {
      SuccessorTable& tab = *tables[static_cast<size_t>(t)];
      Column c;
      std::int64_t swept = 0;
      for (std::int64_t col = 0; col < s.columns; ++col) {
        s.colbox.unlinear(col, c.cidx);
        if ((threads > 1 || split.split()) && !split.owns(c.cidx, t)) continue;
        if (stoppable && swept++ % kStopEvery == 0 && (stop.load(std::memory_order_relaxed) || o.stop())) {
          stop = true;
          return;
        }
        c.reset(s);
        sweep_column(s, tab, c, order, d.inputs);
      }
    });
    if (stop) {
      stopped = true;
      return k;
    }
    for (auto& tab : tables) tab->next_generation();

    // Step k's winning set, this rank's cells and (split) the others' bits.
    split.exchange_winning(d.boxes[k], &d.inputs[static_cast<size_t>(s.off)], kLosing, win);
    std::int64_t count = 0;
    for (const std::uint8_t w : win) count += w;
    fig.winning_cells_per_step[k] = count;
    if (o.progress) o.progress(T - k, T);
    if (count == 0) break;  // nothing can reach an empty set: earlier steps lose too
  }
  // Every rank's inputs of the swept steps, so that each holds the whole controller.
  split.exchange_inputs(d.boxes, d.offsets, std::max(k, 0), T - 1, d.inputs);
  return k;
}

// The result once the sweep ended at step k (-1: complete): the controller when x_0's cell is
// winning and, between the samples, its period enclosures hold.
TrackResult finish_track(const TrackingProblem& p, int k, ControllerData d, const std::string& enclosure_failure,
                         GridFigures fig, TrackResult r) {
  TrackerStats& st = r.stats;
  GridController ctl(std::move(d));
  fig.initial_state_winning = k < 0 && ctl.winning(p.nominal.x[0].data(), 0);
  // A stated initial set: every cell it meets must be winning at step 0 (its box rounded outward).
  std::int64_t initial_losing = 0;
  const bool stated = p.initial_radius.size() > 0;
  if (fig.initial_state_winning && stated) {
    const int n = static_cast<int>(p.nominal.x[0].size());
    std::vector<double> lo(n), hi(n);
    for (int i = 0; i < n; ++i) {
      const double r = i < p.initial_radius.size() ? p.initial_radius[i] : 0.0;
      lo[i] = (Interval(p.nominal.x[0][i]) - Interval(r)).lower();
      hi[i] = (Interval(p.nominal.x[0][i]) + Interval(r)).upper();
    }
    initial_losing = ctl.losing_in_box(lo.data(), hi.data(), 0);
    fig.initial_state_winning = initial_losing == 0;
  }
  fig.publish(st);
  if (fig.initial_state_winning && !enclosure_failure.empty()) {
    r.status = TrackerStatus::NoController;
    r.message = "agent " + p.agent + ": x_0's cell is winning, but " + enclosure_failure;
    st.peak_memory_bytes = peak_rss_bytes();
    return r;
  }
  st.peak_memory_bytes = peak_rss_bytes();
  if (fig.initial_state_winning) {
    r.status = TrackerStatus::ControllerFound;
    r.controller = std::make_shared<GridController>(std::move(ctl));
    r.message = "agent " + p.agent + (stated ? ": every cell of the stated initial set is winning" : ": x_0's cell is winning");
  } else {
    r.status = TrackerStatus::NoController;
    r.message = "agent " + p.agent +
                (initial_losing > 0 ? ": " + std::to_string(initial_losing) + " cell(s) of the stated initial set (x0 +- x0_radius) are not winning"
                                    : ": x_0's cell is not winning") +
                (k >= 0 ? " (the winning set is empty from step " + std::to_string(k) + " backwards)" : "");
    if (k >= 0) {
      r.failure.kind = TrackFailureKind::EmptyWinningSet;
      r.failure.step = k;
    }
  }
  return r;
}

}  // namespace

long long peak_rss_bytes() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<long long>(ru.ru_maxrss) * 1024;
}

TrackResult synthesize_track(const TrackingProblem& p, const Options& o) {
  const Stopwatch clock;
  UniformGrid g;
  InputGrid ug;
  if (const std::string e = check_track(p, g, ug); !e.empty()) return invalid_input("agent " + p.agent + ": " + e);
  TrackResult r;
  const Dynamics& f = *p.dynamics;
  const int T = static_cast<int>(p.nominal.x.size()) - 1;
  std::vector<bool> inv = invariant_coords(f);
  ControllerData d = controller_header(f, p.agent, p.tau, g, ug, p.tube.w);
  d.eps = to_std(p.tube.eps);

  TrackerStats& st = r.stats;
  GridFigures fig;
  const std::int64_t total = lay_out_tube(p, g, ug, d, st, fig);
  fig.winning_cells_per_step.assign(static_cast<size_t>(T + 1), 0);
  for (int k = 0; k <= T; ++k) {
    if (d.boxes[k].empty()) {
      r.status = TrackerStatus::NoController;
      r.message = "agent " + p.agent + ": the eps box of step " + std::to_string(k) + " contains no whole grid cell";
      st.peak_memory_bytes = peak_rss_bytes();
      fig.publish(st);
      return r;
    }
  }
  if (static_cast<double>(total) * 2.0 > o.memory_budget_bytes) {
    r.status = TrackerStatus::ResourceLimit;
    r.message = "agent " + p.agent + ": the tube's controller table exceeds the memory budget";
    fig.publish(st);
    return r;
  }
  d.inputs.assign(static_cast<size_t>(total), kLosing);
  for (const IndexBox& b : d.boxes) drop_unshiftable(g, b, inv);

  SuccessorBox sb(f, d.w, o.successor, o.hook);
  const int threads = std::max(1, o.threads);
  const SweepSplit split(o.collective, threads, inv);  // which rank and thread owns each column
  auto tables = make_tables(threads, sb, g, ug, inv, o.prefilter_substeps);
  bool stopped = false;
  const int k = backward_sweep(p, o, ug, inv, split, tables, d, fig, stopped);

  const double box_seconds = sum_tables(tables, st.boxes_computed);
  st.boxes_computed = split.sum(st.boxes_computed);  // over the ranks: the same figure as one process's
  record_times(box_seconds, threads, clock, st);
  if (stopped) {
    r.status = TrackerStatus::ResourceLimit;
    r.message = "agent " + p.agent + ": stopped by the run after " + number_text(clock.seconds(), 3) + " s, " +
                std::to_string(T - 1 - k) + " of " + std::to_string(T) + " backward steps swept";
    st.peak_memory_bytes = peak_rss_bytes();
    fig.publish(st);
    return r;
  }

  // Between the samples: only for a complete sweep (the controller is used from step 0).
  std::string enclosure_failure;
  if (k < 0) {
    const Stopwatch enclosure_clock;
    EnclosureOptions eo;
    eo.substeps = o.enclosure_substeps;
    eo.block = o.enclosure_block;
    eo.threads = threads;
    eo.collective = split.split() ? o.collective : nullptr;
    if (!compute_period_enclosures(p, inv, sb, eo, d, enclosure_failure)) d.enclosures.clear();
    st.enclosure_time_s = enclosure_clock.seconds();
    st.enclosure_substeps = o.enclosure_substeps;
  }
  return finish_track(p, k, std::move(d), enclosure_failure, std::move(fig), std::move(r));
}

}  // namespace marsyn::abcd
