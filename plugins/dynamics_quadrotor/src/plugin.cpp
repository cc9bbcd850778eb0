#include "marsyn/plugin.hpp"
#include "quadrotor.hpp"

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::Dynamics, marsyn::models::Quadrotor>(
    "quadrotor",
    "rigid-body quadrotor: 12 states (position, ZYX Euler angles, velocity, body rates), input (thrust per "
    "mass, torques per inertia)"))
