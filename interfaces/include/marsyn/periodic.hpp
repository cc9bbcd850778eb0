#pragma once
// Angles on the circle and their lift (Dynamics::periodic, docs/problem-format.md "Periodic
// coordinates"). The method plans, tracks and certifies an angle as a real number (the lift), so
// a turn through +-pi is a continuous path; a robot whose sensor reports the angle modulo a turn
// hands the controller its branch nearest the step's reference (the nominal x_k in plan.json,
// docs/deploy.md) with lift_angle. Header-only, for plugins, core and users' code.
#include <cmath>

namespace marsyn {

inline constexpr double kTurn = 6.283185307179586;  // fl(2 pi)

// The angle `measured` (on any branch) moved by whole turns to within half a turn of
// `reference`. std::remainder is exact; the result differs from the real lift by the rounding
// of measured - reference and of the final sum and by turns x |2 pi - fl(2 pi)| (2.4e-16 per
// turn): a reading error of order 1e-15 rad for references within a few turns (docs/deploy.md).
// A reading already within half a turn of the reference is returned as it is, bit for bit: the
// lifted states of the verification's runs, and a robot that reads the lift, see no rounding.
inline double lift_angle(double measured, double reference) {
  const double d = measured - reference;
  return std::fabs(d) <= 0.5 * kTurn ? measured : reference + std::remainder(d, kTurn);
}

// The shortest signed difference a - b on the circle, in [-pi, pi].
inline double angle_difference(double a, double b) { return std::remainder(a - b, kTurn); }

}  // namespace marsyn
