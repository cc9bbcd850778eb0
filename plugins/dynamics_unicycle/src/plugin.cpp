#include "marsyn/plugin.hpp"
#include "unicycle.hpp"

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::Dynamics, marsyn::models::Unicycle>(
    "unicycle", "planar unicycle: state (x, y, theta), input (speed, turn rate)"))
