#include "disturbance_fields.hpp"

#include <algorithm>
#include <cmath>

#include "field_text.hpp"
#include "marsyn/directed_rounding.hpp"

namespace marsyn::loader {
namespace {

// The largest |s| over [lo, hi] grown by a little: a tracker reading only the constant bound
// argues that the state stays in X, and a first exit needs W on a neighbourhood of X
// (docs/soundness.md section 12).
double largest_magnitude(double lo, double hi) {
  const double m = std::max(std::fabs(lo), std::fabs(hi));
  return fast_detail::add_up(m, fast_detail::mul_up(1e-9, m + 1));
}

DisturbanceGrowth read_growth(const yaml::Field& f, const std::string& name, const AgentSpec& a, int n,
                              const std::string& sn) {
  const auto states = a.dynamics->state_names(), inputs = a.dynamics->input_names();
  const auto is = std::find(states.begin(), states.end(), name);
  const auto iu = std::find(inputs.begin(), inputs.end(), name);
  if (is == states.end() && iu == inputs.end()) {
    std::vector<std::string> all(states);
    all.insert(all.end(), inputs.begin(), inputs.end());
    const std::string near = yaml::nearest(name, all);
    f.fail("unknown coordinate '" + name + "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)") +
           ": W grows with a state or an input of '" + a.dynamics_type + "' (states " + join(states) +
           "; inputs " + join(inputs) + ")");
  }
  if (is != states.end() && iu != inputs.end())
    f.fail("'" + name + "' names both a state and an input of '" + a.dynamics_type + "'");
  DisturbanceGrowth g;
  g.input = is == states.end();
  g.index = static_cast<int>(g.input ? iu - inputs.begin() : is - states.begin());
  g.name = name;
  g.gain = f.non_negative_vector(n, sn + " (one gain per state coordinate of W)");
  return g;
}

}  // namespace

void read_disturbance(const yaml::Field& f, AgentSpec& a, const std::string& sn) {
  const int n = a.dynamics->state_dim();
  if (!f.is_map()) {
    a.tube.w = f.non_negative_vector(n, sn);
    return;
  }
  f.allow_only({"base", "per"});
  a.tube.w_base = f.required("base").non_negative_vector(n, sn);
  a.tube.w_growth.clear();
  if (const yaml::Field per = f.child("per"); per.present()) {
    per.expect_map();
    for (const std::string& name : per.keys()) a.tube.w_growth.push_back(read_growth(per.child(name), name, a, n, sn));
  }
  // The constant bound every reader of w alone takes: W at its largest over X and U.
  a.tube.w = a.tube.w_base;
  for (const DisturbanceGrowth& g : a.tube.w_growth) {
    const Box& b = g.input ? a.input_bounds : a.state_bounds;
    const double s = largest_magnitude(b.lo[g.index], b.hi[g.index]);
    for (int i = 0; i < n; ++i)
      a.tube.w[i] = fast_detail::add_up(a.tube.w[i], fast_detail::mul_up(g.gain[i], s));
  }
  if (!a.tube.w.allFinite()) f.fail("W at its largest over the state and input bounds is not finite; bound the coordinates W grows with");
  if (a.tube.w_growth.empty()) a.tube.w_base.resize(0);  // {base} alone: a constant W
}

}  // namespace marsyn::loader
