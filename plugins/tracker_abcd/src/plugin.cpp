#include "abcd_tracker.hpp"
#include "marsyn/plugin.hpp"

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::Tracker, marsyn::abcd::AbcdTracker>(
    "abcd", "tube-local abstraction with sound growth-bound successor boxes; time-indexed controller"))
