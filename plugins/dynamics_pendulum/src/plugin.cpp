#include "marsyn/plugin.hpp"
#include "pendulum.hpp"

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::Dynamics, marsyn::models::Pendulum>(
    "pendulum", "pendulum of paper Sec. 3.5: state (angle, rate), input torque"))
