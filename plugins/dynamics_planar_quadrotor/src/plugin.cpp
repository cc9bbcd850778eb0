#include "marsyn/plugin.hpp"
#include "planar_quadrotor.hpp"

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::Dynamics, marsyn::models::PlanarQuadrotor>(
    "planar_quadrotor",
    "planar quadrotor: state (x, z, phi, vx, vz, omega), input (thrust per mass, torque per inertia)"))
