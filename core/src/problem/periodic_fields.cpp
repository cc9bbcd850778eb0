#include "periodic_fields.hpp"

#include <cmath>
#include <limits>

#include "marsyn/number_text.hpp"

namespace marsyn::loader {

namespace {

constexpr double kTurn = 6.283185307179586;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool says_any(const yaml::Field& e) { return e.is_scalar() && e.text() == "any"; }

Eigen::VectorXd entries(const yaml::Field& f, int n, const std::string& why, const std::vector<bool>& any_allowed,
                        const std::string& what_any) {
  if (!f.present()) f.fail("missing value: expected a list of numbers");
  if (!f.is_sequence()) f.fail("expected a list of numbers like [1, 2, 3]");
  if (static_cast<int>(f.size()) != n)
    f.fail("expected " + std::to_string(n) + " numbers (" + why + "), got " + std::to_string(f.size()));
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) {
    const yaml::Field e = f[static_cast<std::size_t>(i)];
    if (says_any(e)) {
      if (!any_allowed[static_cast<std::size_t>(i)]) e.fail("expected a number; 'any' is allowed " + what_any);
      v[i] = kNaN;
    } else {
      v[i] = e.real();
    }
  }
  return v;
}

}  // namespace

Box read_box_any(const yaml::Field& f, int n, const std::string& why, const std::vector<bool>& any_allowed,
                 const std::string& what_any) {
  f.expect_map();
  Box b;
  if (f.child("center").present() || f.child("radius").present()) {
    f.allow_only({"center", "radius"});
    const Eigen::VectorXd c = entries(f.required("center"), n, why, any_allowed, what_any);
    const Eigen::VectorXd r = entries(f.required("radius"), n, why, any_allowed, what_any);
    for (int i = 0; i < n; ++i) {
      if (std::isnan(r[i]) != std::isnan(c[i]) && std::isnan(c[i]))
        f.child("center")[static_cast<std::size_t>(i)].fail("a centre 'any' needs the radius 'any' too");
      if (!std::isnan(r[i]) && !(r[i] >= 0))
        f.child("radius")[static_cast<std::size_t>(i)].fail("expected a non-negative number, got " + number_text(r[i]));
    }
    b = {c - r, c + r};  // NaN where the radius says any
    for (int i = 0; i < n; ++i)
      if (std::isnan(r[i])) b.lo[i] = b.hi[i] = kNaN;
  } else {
    f.allow_only({"lo", "hi"});
    b = {entries(f.required("lo"), n, why, any_allowed, what_any), entries(f.required("hi"), n, why, any_allowed, what_any)};
    for (int i = 0; i < n; ++i) {
      if (std::isnan(b.lo[i]) != std::isnan(b.hi[i]))
        (std::isnan(b.lo[i]) ? f.child("hi") : f.child("lo"))[static_cast<std::size_t>(i)].fail(
            "'any' on one side only; write 'any' for both lo and hi");
      if (b.lo[i] > b.hi[i])
        f.child("lo")[static_cast<std::size_t>(i)].fail("lower bound " + number_text(b.lo[i]) + " exceeds upper bound " +
                                                        number_text(b.hi[i]));
    }
  }
  return b;
}

std::string bounds_any_rule(const Dynamics& dyn) {
  const std::vector<bool> periodic = dyn.periodic();
  const auto names = dyn.state_names();
  std::string list;
  for (std::size_t i = 0; i < periodic.size() && i < names.size(); ++i)
    if (periodic[i]) list += (list.empty() ? "" : ", ") + names[i];
  if (list.empty() && dyn.type().rfind("equations:", 0) == 0)
    return "only in the bounds of a periodic coordinate, and these equations declare none (`periodic: [theta]` beside `states` declares one)";
  return list.empty() ? "only in the bounds of a periodic coordinate, and the dynamics '" + dyn.type() + "' has none"
                      : "only in the bounds of a periodic coordinate (the dynamics '" + dyn.type() + "' turns freely in " + list + ")";
}

void lift_periodic(AgentSpec& a) {
  const std::vector<bool> periodic = a.dynamics->periodic();
  for (int i = 0; i < a.n(); ++i) {
    const bool p = i < static_cast<int>(periodic.size()) && periodic[static_cast<std::size_t>(i)];
    double &lo = a.state_bounds.lo[i], &hi = a.state_bounds.hi[i];
    if (p && std::isnan(lo)) {
      lo = a.x0[i] - kFreeTurns * kTurn;
      hi = a.x0[i] + kFreeTurns * kTurn;
    } else if (p && hi - lo < kTurn && !(lo <= a.x0[i] && a.x0[i] <= hi)) {
      // The arc as written may be another branch than x0's: the one holding x0, when one does.
      const double k = std::floor((a.x0[i] - lo) / kTurn);
      if (lo + k * kTurn <= a.x0[i] && a.x0[i] <= hi + k * kTurn) lo += k * kTurn, hi += k * kTurn;
    }
  }
  lift_box(a.goal, a);
}

void lift_box(Box& box, const AgentSpec& a) {
  const std::vector<bool> periodic = a.dynamics->periodic();
  for (int i = 0; i < a.n(); ++i) {
    const bool p = i < static_cast<int>(periodic.size()) && periodic[static_cast<std::size_t>(i)];
    const double lo = a.state_bounds.lo[i], hi = a.state_bounds.hi[i];
    double &glo = box.lo[i], &ghi = box.hi[i];
    if (std::isnan(glo)) {
      glo = lo;
      ghi = hi;
    } else if (p && ghi - glo < kTurn) {
      // The branch nearest x0 (the shorter way round) among those inside the bounds; the nearest
      // overall when none fits (the goal's check then says so).
      const double mid = 0.5 * (glo + ghi);
      const double k0 = std::nearbyint((a.x0[i] - mid) / kTurn);
      double best = k0;
      bool found = false;
      for (double k = k0 - 3; k <= k0 + 3; ++k) {
        const bool fits = lo <= glo + k * kTurn && ghi + k * kTurn <= hi;
        if (fits && (!found || std::abs(mid + k * kTurn - a.x0[i]) < std::abs(mid + best * kTurn - a.x0[i]))) best = k, found = true;
      }
      glo += best * kTurn;
      ghi += best * kTurn;
    }
  }
}

void check_periodic_eps(const AgentSpec& a, const yaml::Field& epsf) {
  const std::vector<bool> periodic = a.dynamics->periodic();
  const auto names = a.dynamics->state_names();
  for (int i = 0; i < a.n() && i < a.tube.eps.size(); ++i)
    if (i < static_cast<int>(periodic.size()) && periodic[static_cast<std::size_t>(i)] && !(a.tube.eps[i] < 0.5 * M_PI)) {
      const yaml::Field at = epsf.is_sequence() ? epsf[static_cast<std::size_t>(i)] : epsf;
      at.fail("eps in '" + names[static_cast<std::size_t>(i)] + "', a periodic coordinate (an angle), is " + number_text(a.tube.eps[i]) +
              "; it must be below pi/2 = 1.571 so that a measured angle lies on one branch of the tube");
    }
}

}  // namespace marsyn::loader
