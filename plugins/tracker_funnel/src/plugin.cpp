#include "funnel_tracker.hpp"
#include "marsyn/plugin.hpp"

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::Tracker, marsyn::funnel::FunnelTracker>(
    "funnel", "time-varying LQR feedback around the nominal, verified with zonotopes; cost polynomial in the dimension"))
