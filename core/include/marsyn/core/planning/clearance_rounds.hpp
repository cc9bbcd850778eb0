#pragma once
// How often one horizon is re-planned with more clearance for requirements short between the
// samples (docs/planning.md, "Fallback"): twice, and up to six times while every requirement
// short is one not yet given clearance at this horizon. In a crowded team each re-plan clears
// the pairs it was told of and another pair comes up short; a longer horizon, planned afresh,
// does not cure that (docs/planning.md, "Fallback", has the fields' figures). A requirement short
// again after its clearance ends the run: that one is not closing.
#include <algorithm>
#include <set>
#include <string>

#include "marsyn/core/planning/robust_check.hpp"

namespace marsyn::planning {

class ClearanceRounds {
 public:
  static constexpr int kRounds = 2;
  static constexpr int kFreshRounds = 6;

  // Whether the horizon is re-planned once more for `c`'s shortfalls between the samples; if so,
  // they count as given clearance.
  bool take(const RobustCheck& c) {
    const auto& s = c.between_shortfalls;
    const bool fresh = std::none_of(s.begin(), s.end(), [&](const auto& e) { return cleared_.count(e.first) > 0; });
    if (taken_ >= (fresh ? kFreshRounds : kRounds)) return false;
    ++taken_;
    for (const auto& e : s) cleared_.insert(e.first);
    return true;
  }
  // A new horizon starts counting again.
  void reset() {
    taken_ = 0;
    cleared_.clear();
  }

 private:
  int taken_ = 0;
  std::set<std::string> cleared_;
};

// Two or more pairs short between the samples at once is a crowd: clearing the named pairs
// brings the next ones up short (a field of 400 unicycles named 15, 8, 4, 5, ... pairs in its
// rounds). What every pair then keeps at the interior points (AssemblyOptions::
// pair_between_extra, added up over the re-plans as the named clearances are): 1.5 times the
// worst pair's shortfall, as the named ones get; 0 when fewer than two pairs are short.
inline double crowd_clearance(const RobustCheck& c) {
  int pairs = 0;
  double worst = 0.0;
  for (const auto& [name, m] : c.between_shortfalls)
    if (m.collision) ++pairs, worst = std::max(worst, -m.margin);
  return pairs >= 2 ? 1.5 * worst : 0.0;
}

}  // namespace marsyn::planning
