#pragma once
// A plugin chosen in the problem file (planner, tracker, dynamics, collision): its name, its
// parameters read and range-checked against the plugin's declaration, and the object created,
// each failure located at the field that caused it.
#include <memory>
#include <string>
#include <utility>

#include "marsyn/core/plugins/plugin_registry.hpp"
#include "marsyn/params.hpp"
#include "yaml_reader.hpp"

namespace marsyn::loader {

using yaml::Field;

// A plugin choice written either as `name` or as {name: ..., params: {...}} (dynamics use `type`).
struct PluginField {
  std::string name;
  Field name_field;
  Field params_field;
};

PluginField read_plugin_field(const Field& f, const std::string& name_key, const std::string& extra_key = {});

std::string unknown_plugin(const PluginRegistry& reg, const std::string& kind, const std::string& name);

// The block's values, typed and range-checked by the plugin's declared ParamSpecs.
Params read_params(const Field& f, const PluginInfo& info);

template <class Interface>
std::pair<std::shared_ptr<Interface>, Params> create_plugin(const PluginRegistry& reg, const PluginField& pf) {
  const std::string kind = PluginKind<Interface>::name;
  const PluginInfo* info = reg.find(kind, pf.name);
  if (!info) pf.name_field.fail(unknown_plugin(reg, kind, pf.name));
  Params params = read_params(pf.params_field, *info);
  try {
    return {reg.create<Interface>(pf.name, params), params};
  } catch (const ParamError& e) {
    Field at = pf.params_field.child(e.field());
    (at.present() ? at : pf.params_field.present() ? pf.params_field : pf.name_field).fail(e.what());
  } catch (const std::exception& e) {
    pf.name_field.fail(std::string("the plugin could not be created: ") + e.what());
  }
}

}  // namespace marsyn::loader
