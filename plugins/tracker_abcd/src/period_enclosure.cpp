#include "period_enclosure.hpp"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <unordered_map>
#include <mutex>
#include <string>
#include <thread>

#include "input_grid.hpp"
#include "marsyn/fast_interval.hpp"
#include "marsyn/period_part.hpp"
#include "successor_cache.hpp"
#include "uniform_grid.hpp"

namespace marsyn::abcd {
namespace {

std::int64_t floor_div(std::int64_t a, std::int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

Interval hull(const Interval& a, const Interval& b) {
  return Interval(std::min(a.lower(), b.lower()), std::max(a.upper(), b.upper()));
}

// Step k's enclosures, one per part of the period: the hull over the step's winning cells.
struct StepBoxes {
  std::vector<Interval> state;      // substeps x n
  std::vector<Interval> workspace;  // substeps x 2
  bool any = false;
};

void accumulate(StepBoxes& acc, const Interval* boxes, const Interval* ws, int substeps, int n) {
  if (!acc.any) {
    acc.state.assign(boxes, boxes + substeps * n);
    acc.workspace.assign(ws, ws + substeps * 2);
    acc.any = true;
    return;
  }
  for (int k = 0; k < substeps * n; ++k) acc.state[k] = hull(acc.state[k], boxes[k]);
  for (int k = 0; k < substeps * 2; ++k) acc.workspace[k] = hull(acc.workspace[k], ws[k]);
}

// A split run's exchange: each rank's steps' boxes (and its failure, if any) to every rank. The
// boxes are hulls of exact interval bounds, so they travel as their doubles, unchanged.
void put(std::vector<std::uint8_t>& b, double v) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  b.insert(b.end(), p, p + sizeof v);
}
double take(const std::vector<std::uint8_t>& b, std::size_t& at) {
  if (at + sizeof(double) > b.size()) throw std::runtime_error("abcd: a rank sent truncated enclosures");
  double v;
  std::memcpy(&v, b.data() + at, sizeof v);
  at += sizeof v;
  return v;
}

bool exchange_steps(const Collective& c, std::vector<StepBoxes>& steps, int S, int n, bool failed, std::string& why) {
  const int R = c.size(), me = c.rank(), T = static_cast<int>(steps.size());
  std::vector<std::uint8_t> mine;
  mine.push_back(failed ? 1 : 0);
  if (failed) {
    mine.insert(mine.end(), why.begin(), why.end());
  } else {
    for (int k = me; k < T; k += R) {
      const StepBoxes& a = steps[static_cast<size_t>(k)];
      for (const Interval& v : a.state) put(mine, v.lower()), put(mine, v.upper());
      for (const Interval& v : a.workspace) put(mine, v.lower()), put(mine, v.upper());
    }
  }
  const auto all = c.allgather(mine);
  for (int q = 0; q < R; ++q) {
    const auto& b = all[static_cast<size_t>(q)];
    if (b.empty()) throw std::runtime_error("abcd: a rank sent no enclosures");
    if (b[0]) {  // the lowest failing rank's reason, the same on every rank
      why.assign(b.begin() + 1, b.end());
      return false;
    }
  }
  for (int q = 0; q < R; ++q) {
    if (q == me) continue;
    const auto& b = all[static_cast<size_t>(q)];
    std::size_t at = 1;
    for (int k = q; k < T; k += R) {
      StepBoxes& a = steps[static_cast<size_t>(k)];
      a.state.resize(static_cast<size_t>(S * n));
      a.workspace.resize(static_cast<size_t>(S * 2));
      for (Interval& v : a.state) {
        const double lo = take(b, at);
        v = Interval(lo, take(b, at));
      }
      for (Interval& v : a.workspace) {
        const double lo = take(b, at);
        v = Interval(lo, take(b, at));
      }
      a.any = true;
    }
  }
  return true;
}

// Winning cells of a step grouped by (their non-invariant block, input): the group's index range.
struct Range {
  std::int64_t lo[kMaxDim], hi[kMaxDim];
};

// What every thread reads: the grids, the model and where the cells' enclosures go.
struct Enclosing {
  const TrackingProblem& p;
  const std::vector<bool>& inv;
  const SuccessorBox& sb;
  const ControllerData& d;
  const UniformGrid g;
  const InputGrid ug;
  const Dynamics& f;
  int n, S, B;
  bool workspace_ok;
  double radius[kMaxDim] = {};

  Enclosing(const TrackingProblem& p_, const std::vector<bool>& inv_, const SuccessorBox& sb_, const ControllerData& d_,
            int S_, int B_)
      : p(p_), inv(inv_), sb(sb_), d(d_), g(d_.origin, d_.eta_x), ug(d_.u_lo, d_.u_hi, d_.eta_u), f(*p_.dynamics),
        n(d_.n), S(S_), B(B_) {
    workspace_ok = p.workspace.linear() ? p.workspace.index.size() == 2 && p.workspace.offset.size() == 2
                                        : p.workspace.footprint < static_cast<int>(f.footprints().size());
    if (p.workspace.linear())
      for (int c = 0; c < 2 && workspace_ok; ++c) workspace_ok = p.workspace.index[c] < n;
    // Canonical cell along invariant coordinates (docs/soundness.md §5 and §9): centred at 0 with
    // radius eta (1/2 + kShiftSlack), which holds every cell enclosure minus its exact centre
    // while the indices stay in the range synthesize_track checked (shift_valid).
    for (int i = 0; i < n; ++i)
      if (inv[i]) radius[i] = (Interval(g.eta()[i]) * Interval(0.5 + kShiftSlack)).upper();
  }

  // Step k's winning cells by (linear index of the cell's block over the non-invariant
  // coordinates, input), the key column * 65536 + input. Blocks of B cells along each
  // coordinate, aligned to multiples of B in absolute indices so that steps share them.
  std::unordered_map<std::uint64_t, Range> groups(int k) const {
    const IndexBox& bk = d.boxes[static_cast<size_t>(k)];
    const std::int64_t off = d.offsets[static_cast<size_t>(k)];
    std::unordered_map<std::uint64_t, Range> out;
    std::int64_t idx[kMaxDim];
    const std::int64_t cells = bk.size();
    for (std::int64_t l = 0; l < cells; ++l) {
      const std::uint16_t j = d.inputs[static_cast<size_t>(off + l)];
      if (j == kLosing) continue;
      bk.unlinear(l, idx);
      std::uint64_t column = 0;
      for (int i = 0; i < n; ++i)
        if (!inv[i]) {
          const std::int64_t first = floor_div(bk.lo[i], B), last = floor_div(bk.hi[i], B);
          column = column * static_cast<std::uint64_t>(last - first + 1) +
                   static_cast<std::uint64_t>(floor_div(idx[i], B) - first);
        }
      auto [it, fresh] = out.try_emplace(column * 65536u + j);
      for (int i = 0; i < n; ++i) {
        if (fresh || idx[i] < it->second.lo[i]) it->second.lo[i] = idx[i];
        if (fresh || idx[i] > it->second.hi[i]) it->second.hi[i] = idx[i];
      }
    }
    return out;
  }

  // The canonical cell's enclosure (S x n boxes) for the whole block `block` (a superset of the
  // group's cells in it), so that it is a function of (block, input) alone; false if none.
  bool canonical(std::uint16_t input, const std::int64_t* block, std::vector<Interval>& out) const {
    Interval cell[kMaxDim];
    double u[kMaxDim];
    for (int i = 0; i < n; ++i)
      cell[i] = inv[i] ? Interval(-radius[i], radius[i]) : hull(g.cell(i, block[i] * B), g.cell(i, block[i] * B + B - 1));
    ug.value(input, u);
    out.resize(static_cast<size_t>(S * n));
    return sb.enclose(cell, u, S, out.data());
  }

  // The canonical boxes shifted to the group: along an invariant coordinate, the rows' exact
  // centres o + (r + 1/2) eta for r in [lo, hi] plus the canonical box.
  void shift(const std::vector<Interval>& canon, const Range& range, std::vector<Interval>& boxes) const {
    for (int s = 0; s < S; ++s)
      for (int i = 0; i < n; ++i) {
        const Interval& b = canon[static_cast<size_t>(s * n + i)];
        if (!inv[i]) {
          boxes[static_cast<size_t>(s * n + i)] = b;
          continue;
        }
        // FastInterval: directed rounding without mode switches (RN holds here, see below).
        const FastInterval eta(g.eta()[i]), o(g.origin()[i]);
        const FastInterval c_lo = o + (FastInterval(static_cast<double>(range.lo[i])) + FastInterval(0.5)) * eta;
        const FastInterval c_hi = o + (FastInterval(static_cast<double>(range.hi[i])) + FastInterval(0.5)) * eta;
        boxes[static_cast<size_t>(s * n + i)] =
            Interval((c_lo + FastInterval(b.lower())).lower(), (c_hi + FastInterval(b.upper())).upper());
      }
  }

  // The workspace boxes (S x 2) of the state boxes (S x n).
  void workspace(const std::vector<Interval>& boxes, std::vector<Interval>& ws) const {
    for (int s = 0; s < S; ++s) {
      Interval* w = &ws[static_cast<size_t>(s * 2)];
      const Interval* x = &boxes[static_cast<size_t>(s * n)];
      if (!workspace_ok) {  // a workspace map this agent cannot evaluate: bound nothing rather than guess
        w[0] = w[1] = Interval::whole();
      } else if (p.workspace.linear()) {
        for (int c = 0; c < 2; ++c) {
          const int at = p.workspace.index[c];
          const FastInterval v = at >= 0 ? FastInterval(x[at]) + FastInterval(p.workspace.offset[c])
                                         : FastInterval(p.workspace.offset[c]);
          w[c] = Interval(v.lower(), v.upper());
        }
      } else {
        workspace_point(f, p.workspace, x, w);  // the model's footprint, in Boost intervals
      }
    }
  }

  // Step k's hull into `acc`, with the thread's cache of canonical enclosures; "" or why not.
  std::string step(int k, std::unordered_map<std::string, std::vector<Interval>>& cache, StepBoxes& acc) const {
    std::vector<Interval> boxes(static_cast<size_t>(S * n)), ws(static_cast<size_t>(S * 2));
    for (const auto& [key, range] : groups(k)) {
      const auto input = static_cast<std::uint16_t>(key % 65536u);
      // The canonical cell's enclosure, per (non-invariant indices, input): every step reuses it.
      std::string ckey(reinterpret_cast<const char*>(&input), sizeof input);
      std::int64_t block[kMaxDim] = {};
      for (int i = 0; i < n; ++i)
        if (!inv[i]) {
          block[i] = floor_div(range.lo[i], B);
          ckey.append(reinterpret_cast<const char*>(&block[i]), sizeof block[i]);
        }
      auto [cit, fresh] = cache.try_emplace(ckey);
      if (fresh && !canonical(input, block, cit->second))
        return "no enclosure between the samples of step " + std::to_string(k) + " (input " + std::to_string(input) + ")";
      shift(cit->second, range, boxes);
      workspace(boxes, ws);
      accumulate(acc, boxes.data(), ws.data(), S, n);
    }
    if (!acc.any) return "step " + std::to_string(k) + " has no winning cell";
    return {};
  }
};

// The steps' hulls as d.enclosures, S per step.
void write_enclosures(const std::vector<StepBoxes>& steps, int S, ControllerData& d) {
  const int n = d.n, T = static_cast<int>(steps.size());
  d.enclosures.clear();
  d.enclosures.reserve(static_cast<size_t>(T * S));
  for (int k = 0; k < T; ++k) {
    const StepBoxes& acc = steps[static_cast<size_t>(k)];
    for (int s = 0; s < S; ++s) {
      PeriodEnclosure e = period_part(k, s, S, d.tau, n, 2);
      for (int i = 0; i < n; ++i) {
        e.state.lo[i] = acc.state[static_cast<size_t>(s * n + i)].lower();
        e.state.hi[i] = acc.state[static_cast<size_t>(s * n + i)].upper();
      }
      for (int c = 0; c < 2; ++c) {
        e.workspace.lo[c] = acc.workspace[static_cast<size_t>(s * 2 + c)].lower();
        e.workspace.hi[c] = acc.workspace[static_cast<size_t>(s * 2 + c)].upper();
      }
      d.enclosures.push_back(std::move(e));
    }
  }
}

}  // namespace

bool compute_period_enclosures(const TrackingProblem& p, const std::vector<bool>& inv, const SuccessorBox& sb,
                               const EnclosureOptions& o, ControllerData& d, std::string& why) {
  const int n = d.n, S = o.substeps, B = std::max(1, o.block);
  const int T = d.tables();
  if (S < 1 || S > SuccessorBox::kMaxEncloseSubsteps) {
    why = "enclosure substeps outside [1, " + std::to_string(SuccessorBox::kMaxEncloseSubsteps) + "]";
    return false;
  }
  const Enclosing enc(p, inv, sb, d, S, B);
  std::vector<StepBoxes> steps(static_cast<size_t>(T));
  // This rank's steps: every R-th from its rank (all of them in one process).
  const int R = o.collective ? std::max(1, o.collective->size()) : 1, me = R > 1 ? o.collective->rank() : 0;
  std::atomic<int> next{me};
  std::atomic<bool> failed{false};
  std::mutex why_lock;
  auto work = [&]() {
    const RoundToNearestScope nearest;  // FastInterval needs round-to-nearest
    std::unordered_map<std::string, std::vector<Interval>> cache;  // per thread: no locks
    for (int k = next.fetch_add(R); k < T && !failed; k = next.fetch_add(R)) {
      std::string e = enc.step(k, cache, steps[static_cast<size_t>(k)]);
      if (!e.empty()) {
        failed = true;
        const std::lock_guard<std::mutex> lock(why_lock);
        why = std::move(e);
        return;
      }
    }
  };
  const int threads = std::max(1, std::min(o.threads, (T - me + R - 1) / R));
  if (threads <= 1) {
    work();
  } else {
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) pool.emplace_back(work);
    for (auto& th : pool) th.join();
  }
  if (R > 1) {
    if (!exchange_steps(*o.collective, steps, S, n, failed, why)) return false;
  } else if (failed) {
    return false;
  }
  write_enclosures(steps, S, d);
  return true;
}

}  // namespace marsyn::abcd
