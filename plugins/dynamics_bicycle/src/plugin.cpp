#include "bicycle.hpp"
#include "marsyn/plugin.hpp"

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::Dynamics, marsyn::models::Bicycle>(
    "bicycle", "kinematic bicycle: state (x, y, theta, v, delta), input (acceleration, steering rate)"))
