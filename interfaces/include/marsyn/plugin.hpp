#pragma once
// The plugin ABI: each shared library exports exactly one C entry point, marsyn_plugin_entry_point,
// returning a static manifest. The loader reads api_version and manifest_size before touching
// anything else and refuses a library built against another API version.
//
// Writing a plugin library (see docs/plugins.md):
//
//   class MyModel : public marsyn::DynamicsModel<MyModel> { ... };
//   MARSYN_PLUGIN_LIBRARY(
//       marsyn::plugin_entry<marsyn::Dynamics, MyModel>("my_model", "what it models"))
//
// A plugin class is constructed from the Params its config block set; it declares them in a
// static `std::vector<marsyn::ParamSpec> param_specs()` (optional: none when absent).
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "marsyn/dynamics.hpp"
#include "marsyn/export.hpp"
#include "marsyn/params.hpp"
#include "marsyn/planner.hpp"
#include "marsyn/tracker.hpp"

// Bump whenever any interface header changes in a way that alters layout or vtables.
// (The versions before 23, each with what it changed: `git log -p interfaces/include/marsyn/plugin.hpp`.)
#define MARSYN_PLUGIN_API_VERSION 23u  // 23: TrackerAssessment::kept_bytes (the tracking stage's memory, predicted)

namespace marsyn {

// Plugin kinds and the interface type each one's create() returns.
template <class T> struct PluginKind;
template <> struct PluginKind<Dynamics> { static constexpr const char* name = "dynamics"; };
template <> struct PluginKind<Planner> { static constexpr const char* name = "planner"; };
template <> struct PluginKind<Tracker> { static constexpr const char* name = "tracker"; };
template <> struct PluginKind<DistanceModel> { static constexpr const char* name = "distance"; };

}  // namespace marsyn

extern "C" {

struct marsyn_plugin_entry {
  const char* kind;     // "dynamics", "planner", "tracker", "distance"
  const char* name;     // unique within a kind, used in configs
  const char* summary;  // one line
  // Returns a new object as a pointer to the kind's interface type (e.g. marsyn::Dynamics*);
  // throws marsyn::ParamError for bad parameters.
  void* (*create)(const marsyn::Params& params);
  std::vector<marsyn::ParamSpec> (*param_specs)();
};

struct marsyn_plugin_manifest {
  std::uint32_t api_version;    // MARSYN_PLUGIN_API_VERSION the library was built with
  std::uint32_t manifest_size;  // sizeof(marsyn_plugin_manifest) of the library
  const char* library;          // the library's name, for messages
  const marsyn_plugin_entry* entries;
  std::size_t entry_count;
};

}  // extern "C"

namespace marsyn {

namespace plugin_detail {
template <class T>
concept HasParamSpecs = requires { { T::param_specs() } -> std::same_as<std::vector<ParamSpec>>; };

template <class T>
std::vector<ParamSpec> specs_of() {
  if constexpr (HasParamSpecs<T>) return T::param_specs();
  else return {};
}
}  // namespace plugin_detail

// Builds a manifest entry for class Impl implementing interface Interface.
template <class Interface, class Impl>
marsyn_plugin_entry plugin_entry(const char* name, const char* summary) {
  return marsyn_plugin_entry{
      PluginKind<Interface>::name, name, summary,
      [](const Params& p) -> void* { return static_cast<Interface*>(new Impl(p)); },
      &plugin_detail::specs_of<Impl>};
}

}  // namespace marsyn

// Defines the library's entry point. Arguments: one or more marsyn::plugin_entry<...>(...).
#define MARSYN_PLUGIN_LIBRARY(...)                                                          \
  extern "C" MARSYN_EXPORT const marsyn_plugin_manifest* marsyn_plugin_entry_point() {        \
    static const marsyn_plugin_entry entries[] = {__VA_ARGS__};                             \
    static const marsyn_plugin_manifest manifest{MARSYN_PLUGIN_API_VERSION,                 \
                                                 sizeof(marsyn_plugin_manifest),            \
                                                 MARSYN_PLUGIN_LIBRARY_NAME, entries,       \
                                                 sizeof(entries) / sizeof(entries[0])};     \
    return &manifest;                                                                       \
  }
