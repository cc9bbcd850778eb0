#pragma once
// The problem file's side of equation models: `dynamics:` given as a map of states, inputs,
// constants, field (and optionally params, definitions, footprints) instead of a plugin name.
// Every rejection is a located ConfigError; errors inside an expression point at the column of
// the offending character in the file when the scalar's text can be found there.
#include <memory>

#include "marsyn/dynamics.hpp"
#include "../yaml_reader.hpp"

namespace marsyn::equations {

// True when the agent's `dynamics` entry describes an equation model: a map with `states` or
// `field`, or a map with only `params` while `defaults.dynamics` is an equation model (the
// defaults' equations with this agent's constants).
bool is_equation_model(const yaml::Field& dynamics, const yaml::Field& default_dynamics);

// Builds the model (throws ConfigError).
std::shared_ptr<const Dynamics> load_equation_dynamics(const yaml::Field& dynamics, const yaml::Field& default_dynamics);

}  // namespace marsyn::equations
