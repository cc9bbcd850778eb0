#include "synthesis.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <thread>

#include "marsyn/stopwatch.hpp"
#include "period_enclosure.hpp"
#include "split_sweep.hpp"
#include "successor_cache.hpp"
#include "tube.hpp"

namespace marsyn::abcd {
namespace {

std::vector<bool> invariant_coords(const Dynamics& f) {
  auto inv = f.field_independent_of();
  if (static_cast<int>(inv.size()) != f.state_dim()) inv.assign(static_cast<size_t>(f.state_dim()), false);
  return inv;
}

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

template <class Fn>
void run_threads(int threads, Fn fn) {
  if (threads <= 1) {
    fn(0);
    return;
  }
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(fn, t);
  for (auto& th : pool) th.join();
}

// Which thread owns a column: a function of the column's absolute indices only, so a column
// keeps its owner (and its cached boxes) from one step to the next; the sum of the indices
// modulo the thread count alternates between neighbouring columns, which balances the load.
int owner(const std::int64_t* idx, const std::vector<bool>& inv, int threads) {
  std::int64_t sum = 0;
  for (size_t i = 0; i < inv.size(); ++i)
    if (!inv[i]) sum += idx[i];
  const std::int64_t r = sum % threads;
  return static_cast<int>(r < 0 ? r + threads : r);
}

std::string check_vector(const Eigen::VectorXd& v, int size, const char* name, bool positive) {
  if (v.size() != size) return std::string(name) + " has " + std::to_string(v.size()) + " entries, expected " + std::to_string(size);
  for (int i = 0; i < size; ++i) {
    if (!std::isfinite(v[i])) return std::string(name) + " is not finite";
    if (positive ? !(v[i] > 0) : !(v[i] >= 0)) return std::string(name) + (positive ? " must be positive" : " must be non-negative");
  }
  return {};
}

std::vector<double> to_std(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

}  // namespace

long long peak_rss_bytes() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<long long>(ru.ru_maxrss) * 1024;
}

TrackResult synthesize_track(const TrackingProblem& p, const SynthesisOptions& o) {
  const Stopwatch clock;
  TrackResult r;
  auto invalid = [&](const std::string& why) {
    r.status = TrackerStatus::InvalidInput;
    r.message = "agent " + p.agent + ": " + why;
    return r;
  };
  if (!p.dynamics) return invalid("no dynamics");
  const Dynamics& f = *p.dynamics;
  const int n = f.state_dim(), m = f.input_dim();
  if (n < 1 || n > kMaxDim || m < 1 || m > kMaxDim) return invalid("unsupported dimensions");
  if (p.nominal.x.size() < 2) return invalid("the nominal trajectory needs at least two states");
  for (const auto& x : p.nominal.x)
    if (x.size() != n || !x.allFinite()) return invalid("a nominal state has the wrong dimension or is not finite");
  for (auto [v, sz, name, pos] : {std::tuple{&p.tube.eps, n, "eps", true}, {&p.tube.eta_x, n, "eta_x", true},
                                  {&p.tube.w, n, "W", false}, {&p.tube.eta_u, m, "eta_u", true}}) {
    const std::string e = check_vector(*v, sz, name, pos);
    if (!e.empty()) return invalid(e);
  }
  if (p.state_bounds.lo.size() != n) return invalid("state bounds have the wrong dimension");
  if (p.input_bounds.lo.size() != m || p.input_bounds.hi.size() != m) return invalid("input bounds have the wrong dimension");
  if (!(p.tau > 0)) return invalid("tau must be positive");

  const int T = static_cast<int>(p.nominal.x.size()) - 1;
  UniformGrid g;
  InputGrid ug;
  try {
    g = UniformGrid(to_std(p.state_bounds.lo), to_std(p.tube.eta_x));
    ug = InputGrid(to_std(p.input_bounds.lo), to_std(p.input_bounds.hi), to_std(p.tube.eta_u));
  } catch (const std::exception& e) {
    return invalid(e.what());
  }
  if (ug.size() >= kTarget) return invalid("more than 65533 grid inputs");
  std::vector<bool> inv = invariant_coords(f);

  ControllerData d;
  d.dynamics_type = f.type();
  d.agent = p.agent;
  d.n = n;
  d.m = m;
  d.tau = p.tau;
  d.origin = g.origin();
  d.eta_x = g.eta();
  d.eps = to_std(p.tube.eps);
  d.w = to_std(p.tube.w);
  d.u_lo = ug.lo();
  d.u_hi = ug.hi();
  d.eta_u = ug.eta();

  TrackerStats& st = r.stats;
  std::int64_t total = 0;
  for (int k = 0; k <= T; ++k) {
    d.boxes.push_back(tube_box(g, p.nominal.x[k].data(), p.tube.eps.data()));
    const std::int64_t cells = d.boxes.back().size();
    st.tube_cells += cells;
    if (k < T) {
      d.offsets.push_back(total);
      total += cells;
      st.state_input_pairs += static_cast<double>(cells) * static_cast<double>(ug.size());
    }
  }
  st.winning_cells_per_step.assign(static_cast<size_t>(T + 1), 0);
  for (int k = 0; k <= T; ++k) {
    if (d.boxes[k].empty()) {
      r.status = TrackerStatus::NoController;
      r.message = "agent " + p.agent + ": the eps box of step " + std::to_string(k) + " contains no whole grid cell";
      st.peak_memory_bytes = peak_rss_bytes();
      return r;
    }
  }
  if (static_cast<double>(total) * 2.0 > o.memory_budget_bytes) {
    r.status = TrackerStatus::ResourceLimit;
    r.message = "agent " + p.agent + ": the tube's controller table exceeds the memory budget";
    return r;
  }
  d.inputs.assign(static_cast<size_t>(total), kLosing);
  // The whole-cell shift needs moderate indices (successor_cache.hpp); beyond them a coordinate
  // simply is not reused.
  for (const IndexBox& b : d.boxes)
    for (int i = 0; i < n; ++i)
      if (inv[i] && (!SuccessorTable::shift_valid(g, i, b.lo[i] - 1000) || !SuccessorTable::shift_valid(g, i, b.hi[i] + 1000)))
        inv[i] = false;

  SuccessorBox sb(f, d.w, o.successor, o.hook);
  const int threads = std::max(1, o.threads);
  const SweepSplit split(o.collective, threads, inv);  // which rank and thread owns each column
  std::vector<std::unique_ptr<SuccessorTable>> tables;
  for (int t = 0; t < threads; ++t) tables.push_back(std::make_unique<SuccessorTable>(sb, g, ug, inv, o.prefilter_substeps));

  std::vector<std::uint8_t> win(static_cast<size_t>(d.boxes[T].size()), 1);
  st.winning_cells_per_step[T] = d.boxes[T].size();
  std::vector<double> uval(static_cast<size_t>(ug.size() * m));
  for (std::int64_t j = 0; j < ug.size(); ++j) ug.value(j, &uval[static_cast<size_t>(j * m)]);
  std::vector<std::int64_t> order(static_cast<size_t>(ug.size()));
  std::vector<double> dist(order.size());

  int k = T - 1;
  for (; k >= 0; --k) {
    const IndexBox& bk = d.boxes[k];
    const IndexBox& bn = d.boxes[k + 1];
    const WinningSet ws(bn, win);

    // Inputs by closeness to the nominal input (in units of eta_u), ties by index.
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

    // Columns: fixed non-invariant indices; rows: the invariant indices. All cells of a column
    // share one relative successor box per input, and its cover is the row's index plus a
    // constant offset, so the rows whose cover stays inside the next tube form a box.
    IndexBox colbox = bk, rowbox = bk;
    for (int i = 0; i < n; ++i) {
      if (inv[i]) colbox.hi[i] = colbox.lo[i];
      else rowbox.lo[i] = rowbox.hi[i] = bk.lo[i];
    }
    const std::int64_t columns = colbox.size(), rows = rowbox.size();
    const std::int64_t off = d.offsets[k];

    // Keeping rejected centre probes in the cache pays when the (column, input) pairs are few
    // (they recur every step); with many, the memory is not worth it.
    const bool keep_rejects = static_cast<double>(columns) * static_cast<double>(ug.size()) <= 262144.0;

    run_threads(threads, [&](int t) {
      SuccessorTable& tab = *tables[static_cast<size_t>(t)];
      // Pending rows of the current column, as row index boxes' multi-indices (compacted as
      // rows are won).
      std::vector<std::int64_t> pend;
      std::vector<std::int64_t> pidx;  // rows x n multi-indices
      std::int64_t cidx[kMaxDim];
      auto in_box = [&](const IndexBox& R, const std::int64_t* ri) {
        for (int i = 0; i < n; ++i)
          if (inv[i] && (ri[i] < R.lo[i] || ri[i] > R.hi[i])) return false;
        return true;
      };
      for (std::int64_t col = 0; col < columns; ++col) {
        colbox.unlinear(col, cidx);
        if ((threads > 1 || split.split()) && !split.owns(cidx, t)) continue;
        pend.resize(static_cast<size_t>(rows));
        pidx.resize(static_cast<size_t>(rows * n));
        for (std::int64_t row = 0; row < rows; ++row) {
          pend[static_cast<size_t>(row)] = row;
          rowbox.unlinear(row, &pidx[static_cast<size_t>(row * n)]);
          for (int i = 0; i < n; ++i)
            if (!inv[i]) pidx[static_cast<size_t>(row * n + i)] = cidx[i];
        }
        for (std::int64_t j : order) {
          if (pend.empty()) break;
          RelBox fresh;
          RelBox* ep = keep_rejects ? &tab.entry(cidx, j) : tab.find(cidx, j);
          if (!ep) ep = &fresh;
          IndexBox R = rowbox;  // rows that may still win with input j
          if (o.prefilter) {
            // Rejected when the rows R narrowed by the probe hull's cover leave no pending row
            // whose whole hull cover is winning. A larger hull only narrows R and grows the
            // covers, so a rejection by part of the probes is a rejection by all of them.
            auto rejects = [&](const RelBox& e, IndexBox& Rr) {
              if (!rows_inside(inv, cidx, e.hlo, e.hhi, bn, Rr)) return true;
              IndexBox cov;
              for (size_t q = 0; q < pend.size(); ++q) {
                const std::int64_t* ri = &pidx[static_cast<size_t>(pend[q] * n)];
                if (!in_box(Rr, ri)) continue;
                tab.cover(e.hlo, e.hhi, ri, cov);
                if (ws.all_winning(cov)) return false;
              }
              return true;
            };
            // Stage 1: the centre alone (cheap rejection).
            tab.probe(*ep, cidx, j, 1);
            bool rejected = ep->has_hull && rejects(*ep, R);
            if (!rejected) {
              // Stage 2: the corners. Entries are stored once the centre probe passes (or
              // always, keep_rejects). Partial hulls (after 2, 4, 8 corners) are tried on a copy
              // of R, so only a rejection can end the stage early; the decision to go on to
              // the box is always taken with the full hull, exactly as without the early exit.
              if (ep == &fresh) ep = &tab.insert(cidx, j, fresh);
              RelBox& e = *ep;
              const int total = tab.total_probes();
              for (int upto : {3, 5, 9}) {
                if (upto >= total || e.probed >= upto) continue;
                tab.probe(e, cidx, j, upto);
                IndexBox Rt = R;
                if (e.has_hull && rejects(e, Rt)) {
                  rejected = true;
                  break;
                }
              }
              if (!rejected) {
                tab.probe(e, cidx, j, total);
                rejected = e.has_hull && rejects(e, R);
              }
            }
            if (rejected) continue;
          }
          if (ep == &fresh) ep = &tab.insert(cidx, j, fresh);
          RelBox& e = *ep;
          tab.box(e, cidx, j);
          if (!e.ok) continue;
          if (!rows_inside(inv, cidx, e.lo, e.hi, bn, R)) continue;
          IndexBox cov;
          size_t keep = 0;
          for (size_t q = 0; q < pend.size(); ++q) {
            const std::int64_t* ri = &pidx[static_cast<size_t>(pend[q] * n)];
            bool won = false;
            if (in_box(R, ri)) {
              tab.cover(e, ri, cov);
              if (ws.all_winning(cov)) {
                d.inputs[static_cast<size_t>(off + bk.linear(ri))] = static_cast<std::uint16_t>(j);
                won = true;
              }
            }
            if (!won) pend[keep++] = pend[q];
          }
          pend.resize(keep);
        }
      }
    });
    for (auto& tab : tables) tab->next_generation();

    // Step k's winning set, this rank's cells and (split) the others' bits.
    split.exchange_winning(bk, &d.inputs[static_cast<size_t>(off)], kLosing, win);
    std::int64_t count = 0;
    for (const std::uint8_t w : win) count += w;
    st.winning_cells_per_step[k] = count;
    if (o.progress) o.progress(T - k, T);
    if (count == 0) break;  // nothing can reach an empty set: earlier steps lose too
  }
  // Every rank's inputs of the swept steps, so that each holds the whole controller.
  split.exchange_inputs(d.boxes, d.offsets, std::max(k, 0), T - 1, d.inputs);

  double box_seconds = 0;
  for (auto& tab : tables) {
    st.boxes_computed += tab->computed();
    box_seconds += tab->seconds();
  }
  st.boxes_computed = split.sum(st.boxes_computed);  // over the ranks: the same figure as one process's
  st.abstraction_time_s = box_seconds / threads;
  st.synthesis_time_s = std::max(0.0, clock.seconds() - st.abstraction_time_s);

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

  GridController ctl(std::move(d));
  st.initial_state_winning = k < 0 && ctl.winning(p.nominal.x[0].data(), 0);
  if (st.initial_state_winning && !enclosure_failure.empty()) {
    r.status = TrackerStatus::NoController;
    r.message = "agent " + p.agent + ": x_0's cell is winning, but " + enclosure_failure;
    st.peak_memory_bytes = peak_rss_bytes();
    return r;
  }
  st.peak_memory_bytes = peak_rss_bytes();
  if (st.initial_state_winning) {
    r.status = TrackerStatus::ControllerFound;
    r.controller = std::make_shared<GridController>(std::move(ctl));
    r.message = "agent " + p.agent + ": x_0's cell is winning";
  } else {
    r.status = TrackerStatus::NoController;
    r.message = "agent " + p.agent + ": x_0's cell is not winning" +
                (k >= 0 ? " (the winning set is empty from step " + std::to_string(k) + " backwards)" : "");
    if (k >= 0) {
      r.failure.kind = TrackFailureKind::EmptyWinningSet;
      r.failure.step = k;
    }
  }
  return r;
}

TrackResult synthesize_reach_avoid(const ReachAvoidProblem& p, const SynthesisOptions& o) {
  const Stopwatch clock;
  TrackResult r;
  auto invalid = [&](const std::string& why) {
    r.status = TrackerStatus::InvalidInput;
    r.message = "reach-avoid: " + why;
    return r;
  };
  if (!p.dynamics) return invalid("no dynamics");
  const Dynamics& f = *p.dynamics;
  const int n = f.state_dim(), m = f.input_dim();
  if (n < 1 || n > kMaxDim || m < 1 || m > kMaxDim) return invalid("unsupported dimensions");
  for (auto [v, sz, name, pos] :
       {std::tuple{&p.eta_x, n, "eta_x", true}, {&p.w, n, "W", false}, {&p.eta_u, m, "eta_u", true}}) {
    const std::string e = check_vector(*v, sz, name, pos);
    if (!e.empty()) return invalid(e);
  }
  for (const Box* b : {&p.domain, &p.safe, &p.target})
    if (b->lo.size() != n || b->hi.size() != n) return invalid("a box has the wrong dimension");
  if (!(p.tau > 0)) return invalid("tau must be positive");
  UniformGrid g;
  InputGrid ug;
  try {
    g = UniformGrid(to_std(p.domain.lo), to_std(p.eta_x));
    ug = InputGrid(to_std(p.input_bounds.lo), to_std(p.input_bounds.hi), to_std(p.eta_u));
  } catch (const std::exception& e) {
    return invalid(e.what());
  }
  if (ug.size() >= kTarget) return invalid("more than 65533 grid inputs");
  auto inner = [&](const Box& b) {
    IndexBox ib;
    ib.n = n;
    for (int i = 0; i < n; ++i) g.inner_range(i, Interval(b.lo[i]), Interval(b.hi[i]), ib.lo[i], ib.hi[i]);
    return ib;
  };
  const IndexBox dom = inner(p.domain), safe = inner(p.safe), target = inner(p.target);
  const std::int64_t cells = dom.size();
  if (static_cast<double>(cells) * 3.0 > o.memory_budget_bytes) {
    r.status = TrackerStatus::ResourceLimit;
    r.message = "reach-avoid: the domain grid exceeds the memory budget";
    return r;
  }
  ControllerData d;
  d.dynamics_type = f.type();
  d.agent = "";
  d.n = n;
  d.m = m;
  d.time_invariant = true;
  d.tau = p.tau;
  d.origin = g.origin();
  d.eta_x = g.eta();
  d.eps.assign(static_cast<size_t>(n), 0.0);
  d.w = to_std(p.w);
  d.u_lo = ug.lo();
  d.u_hi = ug.hi();
  d.eta_u = ug.eta();
  d.boxes = {dom};
  d.offsets = {0};
  d.inputs.assign(static_cast<size_t>(cells), kLosing);
  TrackerStats& st = r.stats;
  st.tube_cells = cells;
  st.state_input_pairs = static_cast<double>(cells) * static_cast<double>(ug.size());

  std::vector<std::uint8_t> win(static_cast<size_t>(cells), 0), candidate(static_cast<size_t>(cells), 0);
  std::int64_t idx[kMaxDim];
  for (std::int64_t l = 0; l < cells; ++l) {
    dom.unlinear(l, idx);
    if (target.contains(idx)) {
      win[static_cast<size_t>(l)] = 1;
      d.inputs[static_cast<size_t>(l)] = kTarget;
    } else if (safe.contains(idx)) {
      bool ok = true;
      if (p.unsafe) {
        double lo[kMaxDim], hi[kMaxDim];
        for (int i = 0; i < n; ++i) {
          const Interval c = g.cell(i, idx[i]);  // outward-rounded cell bounds
          lo[i] = c.lower();
          hi[i] = c.upper();
        }
        ok = !p.unsafe(lo, hi);
      }
      candidate[static_cast<size_t>(l)] = ok ? 1 : 0;
    }
  }
  SuccessorBox sb(f, d.w, o.successor, o.hook);
  const int threads = std::max(1, o.threads);
  std::vector<bool> inv = invariant_coords(f);
  for (int i = 0; i < n; ++i)
    if (inv[i] && (!SuccessorTable::shift_valid(g, i, dom.lo[i] - 1000) || !SuccessorTable::shift_valid(g, i, dom.hi[i] + 1000)))
      inv[i] = false;
  std::vector<std::unique_ptr<SuccessorTable>> tables;
  for (int t = 0; t < threads; ++t) tables.push_back(std::make_unique<SuccessorTable>(sb, g, ug, inv, o.prefilter_substeps));
  // Jacobi iteration: round r admits cells whose successor lies in round r-1's winning set, so
  // the stored input decreases a ranking (the round) and the controller reaches the target.
  for (;;) {
    const WinningSet ws(dom, win);
    std::vector<std::vector<std::pair<std::int64_t, std::uint16_t>>> found(static_cast<size_t>(threads));
    run_threads(threads, [&](int t) {
      SuccessorTable& tab = *tables[static_cast<size_t>(t)];
      std::int64_t cidx[kMaxDim];
      for (std::int64_t l = 0; l < cells; ++l) {
        if (!candidate[static_cast<size_t>(l)] || win[static_cast<size_t>(l)]) continue;
        dom.unlinear(l, cidx);
        if (threads > 1 && owner(cidx, inv, threads) != t) continue;
        for (std::int64_t j = 0; j < ug.size(); ++j) {
          RelBox& e = tab.entry(cidx, j);
          tab.box(e, cidx, j);
          IndexBox cov;
          if (tab.cover(e, cidx, cov) && dom.contains(cov) && ws.all_winning(cov)) {
            found[static_cast<size_t>(t)].emplace_back(l, static_cast<std::uint16_t>(j));
            break;
          }
        }
      }
    });
    bool changed = false;
    for (const auto& v : found)
      for (auto [l, j] : v) {
        d.inputs[static_cast<size_t>(l)] = j;
        win[static_cast<size_t>(l)] = 1;
        changed = true;
      }
    if (!changed) break;
  }
  double box_seconds = 0;
  for (auto& tab : tables) {
    st.boxes_computed += tab->computed();
    box_seconds += tab->seconds();
  }
  std::int64_t count = 0;
  for (auto v : win) count += v;
  st.winning_cells_per_step = {count};
  st.abstraction_time_s = box_seconds / threads;
  st.synthesis_time_s = std::max(0.0, clock.seconds() - st.abstraction_time_s);
  st.peak_memory_bytes = peak_rss_bytes();
  if (count > 0) {
    r.status = TrackerStatus::ControllerFound;
    r.controller = std::make_shared<GridController>(std::move(d));
    r.message = "reach-avoid: " + std::to_string(count) + " winning cells";
  } else {
    r.status = TrackerStatus::NoController;
    r.message = "reach-avoid: no winning cell";
  }
  return r;
}

}  // namespace marsyn::abcd
