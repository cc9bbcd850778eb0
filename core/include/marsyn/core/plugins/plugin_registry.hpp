#pragma once
// Finds plugin libraries, checks their API version, and creates plugin objects. Every object
// created holds a reference to its library, so the library stays loaded while the object lives
// (gz-plugin style), even after the registry is gone.
//
// Search order: the config's plugin_paths, then MARSYN_PLUGIN_PATH (':'-separated), then the
// plugin directory next to the executable (../lib/marsyn/plugins), then the install directory.
// The first library providing a (kind, name) wins; later duplicates are reported as shadowed.
#include <memory>
#include <string>
#include <vector>

#include "marsyn/plugin.hpp"

namespace marsyn {

class PluginLibrary;  // an open shared library

struct PluginInfo {
  std::string kind, name, summary;
  std::string library_path;
  std::vector<ParamSpec> params;
};

// A library that could not be used, with the reason (wrong API version, missing entry point,
// dlopen failure).
struct PluginProblem {
  std::string library_path;
  std::string reason;
  bool explicit_path = false;  // came from the config's plugin_paths
};

class PluginRegistry {
 public:
  // Scans the directories (or single library files) in `config_paths`, then the default search
  // path. Problems with libraries are collected, not thrown; see problems().
  explicit PluginRegistry(const std::vector<std::string>& config_paths = {});
  ~PluginRegistry();
  PluginRegistry(const PluginRegistry&) = delete;
  PluginRegistry& operator=(const PluginRegistry&) = delete;

  const std::vector<PluginInfo>& plugins() const { return infos_; }
  const std::vector<PluginProblem>& problems() const { return problems_; }
  const std::vector<std::string>& search_path() const { return search_path_; }
  const PluginInfo* find(const std::string& kind, const std::string& name) const;
  // Names of all plugins of a kind, for "expected one of ..." messages.
  std::vector<std::string> names(const std::string& kind) const;

  // Creates a plugin object. Throws std::out_of_range when unknown, ParamError for bad params.
  template <class Interface>
  std::shared_ptr<Interface> create(const std::string& name, const Params& params = {}) const {
    std::shared_ptr<void> lib;
    void* raw = create_raw(PluginKind<Interface>::name, name, params, lib);
    auto* obj = static_cast<Interface*>(raw);
    // The deleter runs in this (core) code: it destroys the object through its virtual
    // destructor, then drops the library reference, which may dlclose it.
    return std::shared_ptr<Interface>(obj, [lib](Interface* p) mutable {
      delete p;
      lib.reset();
    });
  }

  static std::vector<std::string> default_search_path();

 private:
  void* create_raw(const std::string& kind, const std::string& name, const Params& params,
                   std::shared_ptr<void>& library) const;
  void scan(const std::string& path, bool explicit_path);
  void load(const std::string& file, bool explicit_path);

  std::vector<std::string> search_path_;
  std::vector<PluginInfo> infos_;
  std::vector<PluginProblem> problems_;
  struct Entry {
    std::shared_ptr<void> library;
    const marsyn_plugin_entry* entry;
  };
  std::vector<Entry> entries_;  // parallel to infos_
};

}  // namespace marsyn
