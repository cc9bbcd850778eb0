#include "controller_file.hpp"

#include "marsyn/binary_file.hpp"
#include "marsyn/periodic.hpp"
#include "marsyn/period_enclosure_file.hpp"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace marsyn::abcd {
namespace {

constexpr char kMagic[8] = {'M', 'A', 'R', 'S', 'Y', 'N', 'C', 'T'};

// The little-endian encoding and the envelope are shared with the other plugins' files.
using binary::fnv1a;
using binary::Reader;
using binary::Writer;

}  // namespace

std::string serialize(const ControllerData& d) {
  Writer p;
  p.str(d.dynamics_type);
  p.str(d.agent);
  p.u32(static_cast<std::uint32_t>(d.n));
  p.u32(static_cast<std::uint32_t>(d.m));
  p.u8(d.time_invariant ? 1 : 0);
  p.f64(d.tau);
  p.reals(d.origin);
  p.reals(d.eta_x);
  p.reals(d.eps);
  p.reals(d.w);
  p.reals(d.u_lo);
  p.reals(d.u_hi);
  p.reals(d.eta_u);
  p.u32(static_cast<std::uint32_t>(d.boxes.size()));
  p.u32(static_cast<std::uint32_t>(d.offsets.size()));
  for (size_t k = 0; k < d.boxes.size(); ++k) {
    for (int i = 0; i < d.n; ++i) p.i64(d.boxes[k].lo[i]);
    for (int i = 0; i < d.n; ++i) p.i64(d.boxes[k].hi[i]);
    if (k < d.offsets.size()) {
      const std::int64_t cells = d.boxes[k].size();
      for (std::int64_t c = 0; c < cells; ++c) p.u16(d.inputs[static_cast<size_t>(d.offsets[k] + c)]);
    }
  }
  // Version 2: the period enclosures (continuous time).
  binary::write_period_enclosures(p, d.enclosures, d.n);
  // Version 3: the periodic coordinates.
  for (int i = 0; i < d.n; ++i) p.u8(i < static_cast<int>(d.periodic.size()) ? d.periodic[static_cast<std::size_t>(i)] : 0);
  return binary::envelope(kMagic, kFormatVersion, p.bytes());
}

ControllerData deserialize(const std::string& s, const std::string& what) {
  const std::string where = "controller file " + what;
  auto fail = [&](const std::string& why) -> void { throw std::runtime_error("controller file " + what + ": " + why); };
  if (s.size() < 8 || std::memcmp(s.data(), kMagic, 8) != 0) fail("not a marsyn abcd controller (bad magic)");
  if (s.size() < 28) fail("truncated header");
  Reader h(s, 8, s.size(), where);
  const std::uint32_t version = h.u32();
  if (version == 1)
    fail("format version 1 was written before controllers carried their enclosures between the samples "
         "(continuous-time guarantee); re-run `marsyn solve` or `marsyn track` to write version " +
         std::to_string(kFormatVersion));
  if (version != 2 && version != kFormatVersion)
    fail("format version " + std::to_string(version) + ", this reader understands " + std::to_string(kFormatVersion));
  const std::uint64_t size = h.uN(8);
  if (size != s.size() - 28) fail("truncated or oversized (payload size does not match file size)");
  Reader t(s, 20 + size, s.size(), where);
  if (t.uN(8) != fnv1a(s.data() + 20, size)) fail("checksum mismatch (corrupt file)");

  Reader r(s, 20, 20 + size, where);
  ControllerData d;
  d.dynamics_type = r.str();
  d.agent = r.str();
  d.n = static_cast<int>(r.u32());
  d.m = static_cast<int>(r.u32());
  if (d.n < 1 || d.n > kMaxDim || d.m < 1 || d.m > kMaxDim) fail("unsupported dimensions");
  d.time_invariant = r.u8() != 0;
  d.tau = r.f64();
  d.origin = r.reals(d.n);
  d.eta_x = r.reals(d.n);
  d.eps = r.reals(d.n);
  d.w = r.reals(d.n);
  d.u_lo = r.reals(d.m);
  d.u_hi = r.reals(d.m);
  d.eta_u = r.reals(d.m);
  const std::uint32_t nboxes = r.u32(), ntables = r.u32();
  if (nboxes == 0 || ntables > nboxes || (d.time_invariant && (nboxes != 1 || ntables != 1)) ||
      (!d.time_invariant && ntables + 1 != nboxes))
    fail("inconsistent step count");
  std::int64_t total = 0;
  for (std::uint32_t k = 0; k < nboxes; ++k) {
    IndexBox b;
    b.n = d.n;
    for (int i = 0; i < d.n; ++i) b.lo[i] = r.i64();
    for (int i = 0; i < d.n; ++i) b.hi[i] = r.i64();
    for (int i = 0; i < d.n; ++i)
      if (b.hi[i] < b.lo[i] - 1 || b.hi[i] - b.lo[i] > (std::int64_t{1} << 31)) fail("bad tube box");
    d.boxes.push_back(b);
    if (k < ntables) {
      const std::int64_t cells = b.size();
      r.need(static_cast<size_t>(cells) * 2);
      d.offsets.push_back(total);
      // resize grows geometrically; an exact reserve per step copied every earlier table again.
      d.inputs.resize(static_cast<size_t>(total + cells));
      for (std::int64_t c = 0; c < cells; ++c) d.inputs[static_cast<size_t>(total + c)] = r.u16();
      total += cells;
    }
  }
  d.enclosures = binary::read_period_enclosures(r, d.n, static_cast<int>(ntables));
  if (version >= 3) {
    d.periodic.resize(static_cast<std::size_t>(d.n));
    for (auto& f : d.periodic) {
      f = r.u8();
      if (f > 1) fail("bad periodic flag");
    }
  }
  if (!r.done()) fail("trailing bytes in payload");
  return d;
}

void write_controller(const ControllerData& d, const std::string& path) {
  const std::string bytes = serialize(d);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot open " + path + " for writing");
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("write to " + path + " failed");
}

std::shared_ptr<const GridController> read_controller(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open controller file " + path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return std::make_shared<GridController>(deserialize(ss.str(), path));
}

GridController::GridController(ControllerData d) : data_(std::move(d)) {
  try {
    grid_ = UniformGrid(data_.origin, data_.eta_x);
    ugrid_ = InputGrid(data_.u_lo, data_.u_hi, data_.eta_u);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("controller: bad grid: ") + e.what());
  }
  for (auto v : data_.inputs)
    if (v != kLosing && v != kTarget && v >= ugrid_.size())
      throw std::runtime_error("controller: input index out of range of the input grid");
  bool periodic = false;
  for (int i = 0; i < data_.n; ++i) periodic = periodic || data_.is_periodic(i);
  if (periodic) {
    reference_.assign(data_.boxes.size() * static_cast<std::size_t>(data_.n), 0.0);
    for (std::size_t k = 0; k < data_.boxes.size(); ++k)
      for (int i = 0; i < data_.n; ++i)
        if (data_.is_periodic(i))
          reference_[k * static_cast<std::size_t>(data_.n) + static_cast<std::size_t>(i)] =
              data_.origin[static_cast<std::size_t>(i)] +
              0.5 * static_cast<double>(data_.boxes[k].lo[i] + data_.boxes[k].hi[i] + 1) * data_.eta_x[static_cast<std::size_t>(i)];
  }
  // The verification asks for an input T x runs times per agent: decoding an index costs two
  // 64-bit divisions per input dimension, a table of the decoded points (the same values) none.
  if (ugrid_.size() * data_.m <= kInputTableMax) {
    input_table_.resize(static_cast<size_t>(ugrid_.size() * data_.m));
    for (std::int64_t j = 0; j < ugrid_.size(); ++j) ugrid_.value(j, input_table_.data() + j * data_.m);
  }
}

std::int64_t GridController::locate(const double* x, int k) const {
  const IndexBox& b = data_.boxes[static_cast<size_t>(k)];
  std::int64_t idx[kMaxDim];
  const bool lifts = !reference_.empty();  // the verification asks T x runs times: one test for most controllers
  for (int i = 0; i < data_.n; ++i) {
    if (!std::isfinite(x[i])) return -1;
    idx[i] = grid_.index(i, lifts && data_.is_periodic(i) ? lift_angle(x[i], reference(k, i)) : x[i]);
  }
  if (!b.contains(idx)) return -1;
  return b.linear(idx);
}

bool GridController::winning(const double* x, int k) const {
  if (data_.time_invariant) k = 0;
  if (k < 0 || k >= static_cast<int>(data_.boxes.size())) return false;
  const std::int64_t l = locate(x, k);
  if (l < 0) return false;
  if (k >= data_.tables()) return true;
  return data_.inputs[static_cast<size_t>(data_.offsets[k] + l)] != kLosing;
}

std::int64_t GridController::losing_in_box(const double* lo, const double* hi, int k) const {
  if (data_.time_invariant) k = 0;
  if (k < 0 || k >= static_cast<int>(data_.boxes.size())) return 1;
  const IndexBox& b = data_.boxes[static_cast<size_t>(k)];
  IndexBox cover;
  cover.n = data_.n;
  for (int i = 0; i < data_.n; ++i) {
    if (!std::isfinite(lo[i]) || !std::isfinite(hi[i]) || lo[i] > hi[i]) return 1;
    cover.lo[i] = grid_.index(i, lo[i]);
    cover.hi[i] = grid_.index(i, hi[i]);
  }
  const std::int64_t cells = cover.size();
  std::int64_t losing = 0, idx[kMaxDim];
  for (std::int64_t l = 0; l < cells; ++l) {
    cover.unlinear(l, idx);
    if (!b.contains(idx)) ++losing;
    else if (k < data_.tables() && data_.inputs[static_cast<size_t>(data_.offsets[k] + b.linear(idx))] == kLosing) ++losing;
  }
  return losing;
}

ControlStatus GridController::input(const double* x, int k, double* u) const {
  if (data_.time_invariant) k = 0;
  if (k < 0 || k >= data_.tables()) return ControlStatus::OutsideHorizon;
  const std::int64_t l = locate(x, k);
  if (l < 0) return ControlStatus::OutsideDomain;
  // This agent's next question comes one period later, from about the same place in the next
  // step's tube (a tracked state keeps its offset from the nominal), and its entry is a cache miss
  // otherwise: the closed-loop verification asks runs x T times per agent, and waited on these
  // loads most of its lookup time. A prefetch only warms the cache; the answers are unchanged.
  if (k + 1 < data_.tables()) {
    const std::int64_t next = data_.offsets[k + 1] + l;
    const std::int64_t end = k + 2 < data_.tables() ? data_.offsets[k + 2] : static_cast<std::int64_t>(data_.inputs.size());
    if (next < end) __builtin_prefetch(data_.inputs.data() + next);
  }
  const std::uint16_t j = data_.inputs[static_cast<size_t>(data_.offsets[k] + l)];
  if (j == kLosing) return ControlStatus::OutsideDomain;
  if (j == kTarget) return ControlStatus::OutsideHorizon;
  if (!input_table_.empty()) std::copy_n(input_table_.data() + static_cast<std::ptrdiff_t>(j) * data_.m, data_.m, u);
  else ugrid_.value(j, u);
  return ControlStatus::Ok;
}

void GridController::write(const std::string& path) const { write_controller(data_, path); }

}  // namespace marsyn::abcd
