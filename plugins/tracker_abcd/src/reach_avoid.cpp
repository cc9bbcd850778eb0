// The whole-domain reach-avoid fixed point (the global ABCD baseline): one time-invariant table.
#include "synthesis.hpp"
#include "synthesis_setup.hpp"
#include "marsyn/stopwatch.hpp"
#include "tube.hpp"

namespace marsyn::abcd {
namespace {

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

// "" or why the problem is not one this synthesis takes; builds the grids.
std::string check_reach_avoid(const ReachAvoidProblem& p, UniformGrid& g, InputGrid& ug) {
  if (std::string e = check_dynamics(p.dynamics.get()); !e.empty()) return e;
  const int n = p.dynamics->state_dim(), m = p.dynamics->input_dim();
  if (std::string e = check_vectors({{&p.eta_x, n, "eta_x", true}, {&p.w, n, "W", false}, {&p.eta_u, m, "eta_u", true}});
      !e.empty())
    return e;
  for (const Box* b : {&p.domain, &p.safe, &p.target})
    if (b->lo.size() != n || b->hi.size() != n) return "a box has the wrong dimension";
  if (!(p.tau > 0)) return "tau must be positive";
  return make_grids(p.domain.lo, p.eta_x, p.input_bounds, p.eta_u, g, ug);
}

IndexBox inner_box(const UniformGrid& g, const Box& b) {
  IndexBox ib;
  ib.n = g.dim();
  for (int i = 0; i < ib.n; ++i) g.inner_range(i, Interval(b.lo[i]), Interval(b.hi[i]), ib.lo[i], ib.hi[i]);
  return ib;
}

// Target cells win at once (input kTarget); safe cells not touching the unsafe set are candidates.
void mark_cells(const ReachAvoidProblem& p, const UniformGrid& g, const IndexBox& dom, ControllerData& d,
                std::vector<std::uint8_t>& win, std::vector<std::uint8_t>& candidate) {
  const int n = g.dim();
  const IndexBox safe = inner_box(g, p.safe), target = inner_box(g, p.target);
  std::int64_t idx[kMaxDim];
  for (std::int64_t l = 0; l < dom.size(); ++l) {
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
}

// Jacobi iteration: round r admits cells whose successor lies in round r-1's winning set, so
// the stored input decreases a ranking (the round) and the controller reaches the target.
void fixed_point(const IndexBox& dom, const InputGrid& ug, const std::vector<bool>& inv,
                 std::vector<std::unique_ptr<SuccessorTable>>& tables, const std::vector<std::uint8_t>& candidate,
                 std::vector<std::uint8_t>& win, ControllerData& d) {
  const int threads = static_cast<int>(tables.size());
  const std::int64_t cells = dom.size();
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
}

}  // namespace

TrackResult synthesize_reach_avoid(const ReachAvoidProblem& p, const Options& o) {
  const Stopwatch clock;
  UniformGrid g;
  InputGrid ug;
  if (const std::string e = check_reach_avoid(p, g, ug); !e.empty()) return invalid_input("reach-avoid: " + e);
  TrackResult r;
  const Dynamics& f = *p.dynamics;
  const int n = f.state_dim();
  const IndexBox dom = inner_box(g, p.domain);
  const std::int64_t cells = dom.size();
  if (static_cast<double>(cells) * 3.0 > o.memory_budget_bytes) {
    r.status = TrackerStatus::ResourceLimit;
    r.message = "reach-avoid: the domain grid exceeds the memory budget";
    return r;
  }
  ControllerData d = controller_header(f, "", p.tau, g, ug, p.w);
  d.time_invariant = true;
  d.eps.assign(static_cast<size_t>(n), 0.0);
  d.boxes = {dom};
  d.offsets = {0};
  d.inputs.assign(static_cast<size_t>(cells), kLosing);
  TrackerStats& st = r.stats;
  GridFigures fig;
  fig.tube_cells = cells;
  st.state_input_pairs = static_cast<double>(cells) * static_cast<double>(ug.size());

  std::vector<std::uint8_t> win(static_cast<size_t>(cells), 0), candidate(static_cast<size_t>(cells), 0);
  mark_cells(p, g, dom, d, win, candidate);
  SuccessorBox sb(f, d.w, o.successor, o.hook);
  const int threads = std::max(1, o.threads);
  std::vector<bool> inv = invariant_coords(f);
  drop_unshiftable(g, dom, inv);
  auto tables = make_tables(threads, sb, g, ug, inv, o.prefilter_substeps);
  fixed_point(dom, ug, inv, tables, candidate, win, d);

  const double box_seconds = sum_tables(tables, st.boxes_computed);
  std::int64_t count = 0;
  for (auto v : win) count += v;
  fig.winning_cells_per_step = {count};
  fig.publish(st);
  record_times(box_seconds, threads, clock, st);
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
