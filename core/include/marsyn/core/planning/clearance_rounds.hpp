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

}  // namespace marsyn::planning
