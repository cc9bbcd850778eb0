// The "fcl" distance plugin: planar obstacles as FCL shapes behind the DistanceModel interface.
#include "fcl_distance.hpp"
#include "marsyn/plugin.hpp"

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::DistanceModel, marsyn::fcl_collision::FclDistance>(
    "fcl", "signed point-obstacle distance and gradient with FCL (boxes, extruded convex polygons)"))
