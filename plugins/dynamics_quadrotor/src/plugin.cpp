#include "marsyn/plugin.hpp"
#include "quadrotor.hpp"

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::Dynamics, marsyn::models::Quadrotor>(
    "quadrotor",
    "rigid-body quadrotor: 12 states x, y, z (world frame, z up), phi, theta, psi (roll, pitch, yaw: ZYX Euler angles), vx, vy, vz "
    "(world frame), p, q, r (body rates, body frame); inputs: thrust per mass (along body z, so hovering needs g), "
    "torques per inertia about the body axes"))
