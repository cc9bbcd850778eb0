#pragma once
// A controller's period enclosures (the continuous-time part of its guarantee) in a controller
// file (binary_file.hpp), the same for every tracker: a u32 count, then per enclosure its step
// (u32), t0, t1, the state box's lo then hi (n each) and the workspace box's lo then hi (2 each).
#include <cstdint>
#include <vector>

#include "marsyn/binary_file.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn::binary {

inline void write_period_enclosures(Writer& p, const std::vector<PeriodEnclosure>& enclosures, int n) {
  p.u32(static_cast<std::uint32_t>(enclosures.size()));
  for (const PeriodEnclosure& e : enclosures) {
    p.u32(static_cast<std::uint32_t>(e.step));
    p.f64(e.t0);
    p.f64(e.t1);
    for (int i = 0; i < n; ++i) p.f64(e.state.lo[i]);
    for (int i = 0; i < n; ++i) p.f64(e.state.hi[i]);
    for (int c = 0; c < 2; ++c) p.f64(e.workspace.lo[c]);
    for (int c = 0; c < 2; ++c) p.f64(e.workspace.hi[c]);
  }
}

// What write_period_enclosures wrote, for a controller of `steps` sampling periods. Certification
// reads these boxes as the controller's promise, so a file is refused (Reader::fail) when its count
// is more than the payload holds (checked before anything is allocated), a step lies outside
// [0, steps), t0 > t1, or a box is inverted or NaN.
inline std::vector<PeriodEnclosure> read_period_enclosures(Reader& r, int n, int steps) {
  const std::uint32_t count = r.u32();
  r.need(static_cast<std::size_t>(count) * static_cast<std::size_t>(20 + 16 * n + 32));
  std::vector<PeriodEnclosure> out;
  out.reserve(count);
  auto box = [&r](int dim) {
    Box b{Eigen::VectorXd(dim), Eigen::VectorXd(dim)};
    for (int i = 0; i < dim; ++i) b.lo[i] = r.f64();
    for (int i = 0; i < dim; ++i) b.hi[i] = r.f64();
    for (int i = 0; i < dim; ++i)
      if (!(b.lo[i] <= b.hi[i])) r.fail("bad period enclosure (an inverted or NaN box)");
    return b;
  };
  for (std::uint32_t q = 0; q < count; ++q) {
    PeriodEnclosure e;
    const std::uint32_t step = r.u32();
    if (steps <= 0 || step >= static_cast<std::uint32_t>(steps)) r.fail("period enclosure for a step outside the horizon");
    e.step = static_cast<int>(step);
    e.t0 = r.f64();
    e.t1 = r.f64();
    if (!(e.t0 <= e.t1)) r.fail("bad period enclosure (t0 > t1)");
    e.state = box(n);
    e.workspace = box(2);
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace marsyn::binary
