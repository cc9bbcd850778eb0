#pragma once
// The a priori enclosure of one step of a disturbed flow (docs/soundness.md section 3): a box B
// with X + [0, h] (f(B, U) + W) inside B holds every solution of x' = f(x, u) + w starting in X,
// for u in U and every measurable w with values in W, over [0, h] (Picard-Lindeloef; the test
// is the operator mapping B into itself). Shared by trackers that enclose flows, so that the
// sound part of their argument is one piece of code.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "marsyn/dynamics.hpp"
#include "marsyn/fast_interval.hpp"

namespace marsyn {

// Second method, for chains of products started from a point (a vehicle at rest: x' = v cos th
// with v' = a), where inflating every coordinate each round makes the candidates outgrow the
// box: Phi(B) = X + [0, h] (f(B, U) + W) is inclusion-monotone and X lies in Phi(X), so iterating
// Phi from X gives increasing boxes that settle on a fixed point for a short enough step; a box
// slightly larger than that point which Phi maps into itself is then the enclosure.
inline bool apriori_enclosure_fixed_point(const Dynamics& f, const FastInterval* x, const FastInterval* u,
                                          const FastInterval* w, const FastInterval& h, int iterations,
                                          FastInterval* out) {
  const int n = f.state_dim();
  const FastInterval t(0.0, h.upper());
  std::vector<FastInterval> b(x, x + n), fb(static_cast<std::size_t>(n)), cand(static_cast<std::size_t>(n));
  auto finite = [](const FastInterval& v) { return std::isfinite(v.lower()) && std::isfinite(v.upper()); };
  for (int it = 0; it < 4 * iterations; ++it) {
    f.field(b.data(), u, fb.data());
    bool settled = true;
    for (int i = 0; i < n; ++i) {
      cand[i] = x[i] + t * (fb[i] + w[i]);
      if (!finite(cand[i])) return false;
      if (!(width(cand[i]) <= width(b[i]) * (1 + 1e-9) + 1e-300)) settled = false;
    }
    b = cand;
    if (settled) break;
  }
  // A slightly larger box, grown only along the coordinates whose image leaves it (by twice the
  // excess): the image of a short step moves little, so the excess shrinks geometrically.
  std::vector<FastInterval> inflated(b);
  for (int i = 0; i < n; ++i) {
    const double r = 1e-9 * (width(b[i]) + mag(b[i])) + 1e-300;
    inflated[i] = FastInterval(b[i].lower() - r, b[i].upper() + r);
  }
  for (int attempt = 0; attempt < 4 * iterations; ++attempt) {
    f.field(inflated.data(), u, fb.data());
    bool inside = true;
    for (int i = 0; i < n; ++i) {
      cand[i] = x[i] + t * (fb[i] + w[i]);
      if (!finite(cand[i])) return false;
      if (!subset(cand[i], inflated[i])) inside = false;
    }
    if (inside) {
      for (int i = 0; i < n; ++i) out[i] = cand[i];
      return true;
    }
    for (int i = 0; i < n; ++i) {
      if (subset(cand[i], inflated[i])) continue;
      const double over = std::max(inflated[i].lower() - cand[i].lower(), cand[i].upper() - inflated[i].upper());
      inflated[i] = FastInterval(std::min(inflated[i].lower(), cand[i].lower()) - over,
                                 std::max(inflated[i].upper(), cand[i].upper()) + over);
      if (!finite(inflated[i])) return false;
    }
  }
  return false;
}

// Returns false when neither method found such a box (the step is too long for the field's
// growth there, or the field is not finite on the boxes tried). `out` gets n boxes;
// it is the image X + [0, h](f(B) + W) of the verified B, which is itself such a box and
// tighter. Runs in round-to-nearest (FastInterval's precondition).
inline bool apriori_enclosure(const Dynamics& f, const FastInterval* x, const FastInterval* u, const FastInterval* w,
                              const FastInterval& h, int iterations, FastInterval* out) {
  const int n = f.state_dim();
  const FastInterval t(0.0, h.upper());
  std::vector<FastInterval> b(static_cast<std::size_t>(n)), fb(static_cast<std::size_t>(n)),
      cand(static_cast<std::size_t>(n));
  f.field(x, u, fb.data());
  for (int i = 0; i < n; ++i) b[i] = x[i] + t * (fb[i] + w[i]);
  for (int it = 0; it < iterations; ++it) {
    // Inflation makes the containment test succeed after a few rounds for a smooth field.
    for (int i = 0; i < n; ++i) {
      const double r = 0.1 * width(b[i]) + 1e-12 * (1.0 + mag(b[i]));
      b[i] = FastInterval(b[i].lower() - r, b[i].upper() + r);
      if (!std::isfinite(b[i].lower()) || !std::isfinite(b[i].upper()))
        return apriori_enclosure_fixed_point(f, x, u, w, h, iterations, out);
    }
    f.field(b.data(), u, fb.data());
    bool inside = true;
    for (int i = 0; i < n; ++i) {
      cand[i] = x[i] + t * (fb[i] + w[i]);
      // An interval with a NaN bound is empty (a subset of anything) and an infinite one bounds
      // nothing: non-finite candidates are rejected explicitly.
      if (!std::isfinite(cand[i].lower()) || !std::isfinite(cand[i].upper()))
        return apriori_enclosure_fixed_point(f, x, u, w, h, iterations, out);
      if (!subset(cand[i], b[i])) inside = false;
    }
    if (inside) {
      for (int i = 0; i < n; ++i) out[i] = cand[i];
      return true;
    }
    for (int i = 0; i < n; ++i) b[i] = hull(b[i], cand[i]);
  }
  return apriori_enclosure_fixed_point(f, x, u, w, h, iterations, out);
}

}  // namespace marsyn
