#pragma once
// Successor boxes per (cell, input), computed once and reused where provably identical:
// along the coordinates the field does not read, a cell's box is the box of the canonical cell
// (those coordinates centred at 0) shifted by the cell's exact centre. The shift is applied in
// whole cells: the cover of the shifted box is the cell's own index plus a constant offset
// range, so one relative box serves a whole "column" of cells, every time step, without any
// floating-point work per cell. One table per thread: no locks, and an entry is a pure function
// of its key, so results never depend on which thread computed it.
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "input_grid.hpp"
#include "marsyn/stopwatch.hpp"
#include "successor_box.hpp"
#include "uniform_grid.hpp"

namespace marsyn::abcd {

// Slack, in cells, for the whole-cell shift: it must exceed the quantizer's preimage slack
// (UniformGrid::cell: 1e-12 (|idx| + 2 + |o| / eta)), which holds while |idx| + |o|/eta <= 4e5
// (checked by the caller through shift_valid()).
inline constexpr double kShiftSlack = 1e-6;

// A cache entry, stored as cell-index offsets from the column's own cell (compact: the cache can
// hold many of them). Ranges beyond +-32767 cells are not representable: such a box is treated
// as "no successor" (it could never fit a tube of that many fewer cells anyway), such a probe
// as absent.
struct RelBox {
  std::uint8_t probed = 0;  // probes done (SuccessorTable::probe): 1 the centre, then corners
  bool boxed = false;
  bool ok = false;      // box computed and bounded (false: never use this input from this cell)
  bool has_hull = false;
  // Probe hull: the index box spanned by the cells that surely contain the exact images of the
  // probes (RK4 images of the centre with w = 0, then of every corner with the disturbance
  // vertex of the same signs). Those images lie in every sound successor box, so its cover
  // contains this index box: a necessary condition, checked before any box is computed.
  std::int16_t hlo[kMaxDim], hhi[kMaxDim];
  // Cover of the sound successor box.
  std::int16_t lo[kMaxDim], hi[kMaxDim];
};

inline bool fits16(std::int64_t v) { return v >= -32767 && v <= 32767; }

// Open-addressing hash table (linear probing, power-of-two capacity): the cache is hit for
// every (column, input) visited, and node-based maps spent more time allocating than the
// lookups themselves.
template <class K, class V, class H>
class FlatMap {
 public:
  V* find(const K& k) {
    if (slots_.empty()) return nullptr;
    for (size_t i = H{}(k) & mask_;; i = (i + 1) & mask_) {
      Slot& s = slots_[i];
      if (s.gen != gen_) return nullptr;
      if (s.key == k) return &s.value;
    }
  }
  // k must not be present.
  V& insert(const K& k, const V& v) {
    if ((count_ + 1) * 2 > slots_.size()) grow();
    for (size_t i = H{}(k) & mask_;; i = (i + 1) & mask_) {
      Slot& s = slots_[i];
      if (s.gen != gen_) {
        s.gen = gen_;
        s.key = k;
        s.value = v;
        ++count_;
        return s.value;
      }
    }
  }
  // O(1): a slot is live only if it carries the current generation.
  void clear() {
    if (++gen_ == 0) {  // wrapped: really reset
      for (auto& s : slots_) s.gen = 0;
      gen_ = 1;
    }
    count_ = 0;
  }
  void swap(FlatMap& o) {
    slots_.swap(o.slots_);
    std::swap(count_, o.count_);
    std::swap(mask_, o.mask_);
    std::swap(gen_, o.gen_);
  }
  size_t size() const { return count_; }
  static constexpr std::size_t slot_bytes() { return sizeof(Slot); }

 private:
  struct Slot {
    std::uint32_t gen = 0;  // live iff equal to the table's gen_
    K key{};
    V value{};
  };
  void grow() {
    std::vector<Slot> old;
    old.swap(slots_);
    const std::uint32_t old_gen = gen_;
    slots_.assign(old.empty() ? 1024 : old.size() * 2, Slot{});
    mask_ = slots_.size() - 1;
    count_ = 0;
    gen_ = 1;
    for (auto& s : old)
      if (s.gen == old_gen) insert(s.key, s.value);
  }
  std::vector<Slot> slots_;
  size_t count_ = 0, mask_ = 0;
  std::uint32_t gen_ = 1;
};

class SuccessorTable {
 public:
  SuccessorTable(const SuccessorBox& sb, const UniformGrid& g, const InputGrid& ug, std::vector<bool> invariant,
                 int probe_substeps = 2)
      : sb_(sb), g_(g), ug_(ug), inv_(std::move(invariant)), probe_substeps_(probe_substeps) {
    n_ = g.dim();
    int free = 0;
    for (int i = 0; i < n_; ++i) {
      if (inv_[i]) radius_[i] = (Interval(g.eta()[i]) * Interval(0.5 + kShiftSlack)).upper();
      else ++free;
    }
    packable_ = free <= 4;
  }

  // Whether a cell index along invariant coordinate i may use the whole-cell shift.
  static bool shift_valid(const UniformGrid& g, int i, std::int64_t idx) {
    return static_cast<double>(std::llabs(idx)) + std::abs(g.origin()[i]) / g.eta()[i] <= 4e5;
  }

  // One cache slot's bytes (the assessment's working-memory figure).
  static constexpr std::size_t slot_bytes() { return FlatMap<Key, RelBox, KeyHash>::slot_bytes(); }
  long long computed() const { return computed_; }
  long long probes() const { return probes_; }
  const std::vector<bool>& invariant() const { return inv_; }
  double seconds() const { return seconds_; }

  // Drops entries not used since the previous call (two generations), which bounds memory by
  // what two consecutive steps touch.
  void next_generation() {
    old_.swap(cur_);
    cur_.clear();
  }

  // The cached entry of the column of idx under input j, or nullptr.
  RelBox* find(const std::int64_t* idx, std::int64_t j) {
    Key key;
    if (!packable_ || !pack(idx, j, key)) return nullptr;
    if (RelBox* hit = cur_.find(key)) return hit;
    if (RelBox* hit = old_.find(key)) return &cur_.insert(key, *hit);
    return nullptr;
  }
  // Stores e (key not present). The reference is valid until the next insert.
  RelBox& insert(const std::int64_t* idx, std::int64_t j, const RelBox& e) {
    Key key;
    if (!packable_ || !pack(idx, j, key)) {
      scratch_ = e;
      return scratch_;
    }
    return cur_.insert(key, e);
  }
  // find, or insert an empty entry.
  RelBox& entry(const std::int64_t* idx, std::int64_t j) {
    if (RelBox* hit = find(idx, j)) return *hit;
    return insert(idx, j, RelBox{});
  }

  // Probes in a fixed order: p = 0 the centre, then the corners (corner_bits). total_probes()
  // of them make the full hull; the hull of a prefix is a subset of it.
  int total_probes() const { return 1 + (n_ <= 4 ? (1 << n_) : 2); }

  // Extends e's probe hull with probes e.probed .. upto-1 (a no-op when already done). Callers
  // may stop early on a rejection: the entry remembers how far it got and later calls resume, so
  // the hull after the last probe never depends on when or by whom it was extended.
  void probe(RelBox& e, const std::int64_t* idx, std::int64_t j, int upto) {
    upto = std::min(upto, total_probes());
    if (e.probed >= upto) return;
    ++probes_;
    const Dynamics& f = sb_.dynamics();
    double u[kMaxDim], x[kMaxDim], w[kMaxDim], img[kMaxDim], clo[kMaxDim], chi[kMaxDim];
    ug_.value(j, u);
    for (int i = 0; i < n_; ++i) {
      // Approximate cell bounds suffice: probes only decide where to look, never admit.
      clo[i] = inv_[i] ? -0.5 * g_.eta()[i] : g_.origin()[i] + static_cast<double>(idx[i]) * g_.eta()[i];
      chi[i] = clo[i] + g_.eta()[i];
    }
    for (int p = e.probed; p < upto; ++p) {
      const std::uint32_t bits = p > 0 ? corner_bits(p) : 0u;
      for (int i = 0; i < n_; ++i) {
        const bool up = (bits >> i) & 1u;
        x[i] = p == 0 ? 0.5 * (clo[i] + chi[i]) : (up ? chi[i] : clo[i]);
        w[i] = p == 0 ? 0.0 : (up ? sb_.w()[i] : -sb_.w()[i]);
      }
      rk4(f, x, u, w, img);
      // The cell of the exact image, if the RK4 error margin leaves no doubt about it.
      std::int64_t c[kMaxDim];
      bool clear = true;
      for (int i = 0; i < n_ && clear; ++i) {
        const double m = 0.01 * g_.eta()[i];
        std::int64_t a, b;
        if (inv_[i]) {
          offsets(i, img[i] - m, img[i] + m, a, b);
        } else {
          a = g_.index(i, img[i] - m) - idx[i];
          b = g_.index(i, img[i] + m) - idx[i];
        }
        if (a != b || !fits16(a)) clear = false;
        c[i] = a;
      }
      if (!clear) continue;
      for (int i = 0; i < n_; ++i) {
        const auto v = static_cast<std::int16_t>(c[i]);
        e.hlo[i] = e.has_hull ? std::min(e.hlo[i], v) : v;
        e.hhi[i] = e.has_hull ? std::max(e.hhi[i], v) : v;
      }
      e.has_hull = true;
    }
    e.probed = static_cast<std::uint8_t>(upto);
  }

  void box(RelBox& e, const std::int64_t* idx, std::int64_t j) {
    if (e.boxed) return;
    Interval cell[kMaxDim];
    for (int i = 0; i < n_; ++i) cell[i] = inv_[i] ? Interval(-radius_[i], radius_[i]) : g_.cell(i, idx[i]);
    double u[kMaxDim];
    ug_.value(j, u);
    ++computed_;
    const Stopwatch box_clock;
    double lo[kMaxDim], hi[kMaxDim];
    e.ok = sb_.compute(cell, u, lo, hi);
    seconds_ += box_clock.seconds();
    for (int i = 0; e.ok && i < n_; ++i) {
      std::int64_t a, b;
      if (inv_[i]) {
        offsets(i, lo[i], hi[i], a, b);
      } else {
        a = g_.index(i, lo[i]) - idx[i];
        b = g_.index(i, hi[i]) - idx[i];
      }
      if (!fits16(a) || !fits16(b)) e.ok = false;
      e.lo[i] = static_cast<std::int16_t>(a);
      e.hi[i] = static_cast<std::int16_t>(b);
    }
    e.boxed = true;
  }

  // Cover offsets along invariant coordinate i of a relative interval [lo, hi]: every state in
  // (exact centre of cell r) + [lo, hi] quantizes into r + [a, b].
  void offsets(int i, double lo, double hi, std::int64_t& a, std::int64_t& b) const {
    a = static_cast<std::int64_t>(std::floor(0.5 + lo / g_.eta()[i] - kShiftSlack));
    b = static_cast<std::int64_t>(std::floor(0.5 + hi / g_.eta()[i] + kShiftSlack));
  }

  // The cover (index range) of cell idx's successor box, or of its probe hull.
  void cover(const std::int16_t* lo, const std::int16_t* hi, const std::int64_t* idx, IndexBox& out) const {
    out.n = n_;
    for (int i = 0; i < n_; ++i) {
      out.lo[i] = idx[i] + lo[i];
      out.hi[i] = idx[i] + hi[i];
    }
  }
  bool cover(const RelBox& e, const std::int64_t* idx, IndexBox& out) const {
    if (!e.ok) return false;
    cover(e.lo, e.hi, idx, out);
    return true;
  }

  // Absolute successor box of a cell, without any reuse (tests).
  bool absolute(const std::int64_t* idx, std::int64_t j, double* lo, double* hi) {
    Interval cell[kMaxDim];
    for (int i = 0; i < n_; ++i) cell[i] = g_.cell(i, idx[i]);
    double u[kMaxDim];
    ug_.value(j, u);
    ++computed_;
    return sb_.compute(cell, u, lo, hi);
  }

 private:
  struct Key {
    std::uint64_t a = 0, b = 0;
    bool operator==(const Key& o) const { return a == o.a && b == o.b; }
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      // splitmix64 finalizer: the table indexes with the low bits, so they must mix all input bits.
      std::uint64_t h = k.a ^ (k.b * 0x9E3779B97F4A7C15ull);
      h ^= h >> 30;
      h *= 0xBF58476D1CE4E5B9ull;
      h ^= h >> 27;
      h *= 0x94D049BB133111EBull;
      h ^= h >> 31;
      return static_cast<size_t>(h);
    }
  };

  // Exact (collision-free) packing: up to 4 non-invariant indices of 24 bits plus the input
  // index; anything outside those ranges is computed without the cache.
  bool pack(const std::int64_t* idx, std::int64_t j, Key& k) const {
    int slot = 0;
    std::uint64_t words[4] = {0, 0, 0, 0};
    for (int i = 0; i < n_; ++i) {
      if (inv_[i]) continue;
      const std::int64_t v = idx[i] + (std::int64_t{1} << 23);
      if (v < 0 || v >= (std::int64_t{1} << 24)) return false;
      words[slot++] = static_cast<std::uint64_t>(v);
    }
    if (j < 0 || j >= (std::int64_t{1} << 32)) return false;
    k.a = words[0] | (words[1] << 24) | ((words[2] & 0xFFFF) << 48);
    k.b = (words[2] >> 16) | (words[3] << 8) | (static_cast<std::uint64_t>(j) << 32);
    return true;
  }

  // Corner of probe p >= 1 as a bit pattern (bit i set: upper bound, disturbance +W_i). The two
  // opposite corners come first: they usually span most of the hull, so a rejection needs few
  // probes. For n > 4 only those two are probed.
  std::uint32_t corner_bits(int p) const {
    const std::uint32_t all = n_ <= 4 ? (1u << n_) - 1u : 0xFFu;
    if (p == 1) return 0u;
    if (p == 2) return all;
    return static_cast<std::uint32_t>(p - 2);  // 1 .. all-1
  }

  void rk4(const Dynamics& f, const double* x0, const double* u, const double* w, double* out) const {
    double x[kMaxDim], y[kMaxDim], k1[kMaxDim], k2[kMaxDim], k3[kMaxDim], k4[kMaxDim];
    std::copy(x0, x0 + n_, x);
    const double h = sb_.options().tau / probe_substeps_;
    auto rhs = [&](const double* z, double* d) {
      f.field(z, u, d);
      for (int i = 0; i < n_; ++i) d[i] += w[i];
    };
    for (int s = 0; s < probe_substeps_; ++s) {
      rhs(x, k1);
      for (int i = 0; i < n_; ++i) y[i] = x[i] + 0.5 * h * k1[i];
      rhs(y, k2);
      for (int i = 0; i < n_; ++i) y[i] = x[i] + 0.5 * h * k2[i];
      rhs(y, k3);
      for (int i = 0; i < n_; ++i) y[i] = x[i] + h * k3[i];
      rhs(y, k4);
      for (int i = 0; i < n_; ++i) x[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    }
    std::copy(x, x + n_, out);
  }

  const SuccessorBox& sb_;
  const UniformGrid& g_;
  const InputGrid& ug_;
  std::vector<bool> inv_;
  int probe_substeps_ = 2;
  int n_ = 0;
  bool packable_ = false;
  double radius_[kMaxDim] = {};
  long long computed_ = 0, probes_ = 0;
  double seconds_ = 0.0;
  RelBox scratch_;
  FlatMap<Key, RelBox, KeyHash> cur_, old_;
};

}  // namespace marsyn::abcd
