#include "double_integrator.hpp"
#include "marsyn/plugin.hpp"

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::Dynamics, marsyn::models::DoubleIntegrator>(
    "double_integrator", "double integrator / vehicle: state (position, speed), input acceleration"))
