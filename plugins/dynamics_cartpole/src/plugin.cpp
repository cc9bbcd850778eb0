#include "cartpole.hpp"
#include "marsyn/plugin.hpp"

MARSYN_PLUGIN_LIBRARY(marsyn::plugin_entry<marsyn::Dynamics, marsyn::models::CartPole>(
    "cartpole", "cart-pole / overhead crane: state (z, z', theta, theta'), input force"))
