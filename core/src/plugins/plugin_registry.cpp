#include "marsyn/core/plugins/plugin_registry.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace marsyn {
namespace {

std::string executable_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

bool is_shared_library(const fs::path& p) {
  const std::string name = p.filename().string();
  return p.extension() == ".so" || name.find(".so.") != std::string::npos;
}

}  // namespace

std::vector<std::string> PluginRegistry::default_search_path() {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("MARSYN_PLUGIN_PATH")) {
    std::stringstream ss(env);
    std::string item;
    while (std::getline(ss, item, ':'))
      if (!item.empty()) dirs.push_back(item);
  }
  const std::string exe = executable_dir();
  if (!exe.empty()) dirs.push_back((fs::path(exe) / MARSYN_RELATIVE_PLUGIN_DIR).lexically_normal().string());
  dirs.push_back(MARSYN_INSTALL_PLUGIN_DIR);
  return dirs;
}

PluginRegistry::PluginRegistry(const std::vector<std::string>& config_paths) {
  for (const auto& p : config_paths) {
    search_path_.push_back(p);
    scan(p, true);
  }
  std::set<std::string> seen;
  for (const auto& p : default_search_path()) {
    std::error_code ec;
    const auto canon = fs::weakly_canonical(p, ec).string();
    if (!seen.insert(ec ? p : canon).second) continue;  // the same directory twice
    search_path_.push_back(p);
    scan(p, false);
  }
}

PluginRegistry::~PluginRegistry() = default;

void PluginRegistry::scan(const std::string& path, bool explicit_path) {
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) {
    load(path, explicit_path);
    return;
  }
  if (!fs::is_directory(path, ec)) {
    if (explicit_path) problems_.push_back({path, "no such file or directory", true});
    return;
  }
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(path, ec))
    if (e.is_regular_file() && is_shared_library(e.path())) files.push_back(e.path());
  std::sort(files.begin(), files.end());  // deterministic precedence within a directory
  for (const auto& f : files) load(f.string(), explicit_path);
}

void PluginRegistry::load(const std::string& file, bool explicit_path) {
  // RTLD_LOCAL: plugins must not see each other's symbols; RTLD_NOW: fail here, not mid-run.
  void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* err = dlerror();
    problems_.push_back({file, std::string("cannot be loaded: ") + (err ? err : "unknown error"), explicit_path});
    return;
  }
  std::shared_ptr<void> lib(handle, [](void* h) { dlclose(h); });
  using EntryPoint = const marsyn_plugin_manifest* (*)();
  auto entry_point = reinterpret_cast<EntryPoint>(dlsym(handle, "marsyn_plugin_entry_point"));
  if (!entry_point) {
    problems_.push_back({file, "is not a marsyn plugin (no marsyn_plugin_entry_point symbol)", explicit_path});
    return;
  }
  const marsyn_plugin_manifest* m = entry_point();
  // Only the first two fields are read before the version is known to match.
  if (!m || m->api_version != MARSYN_PLUGIN_API_VERSION) {
    std::ostringstream why;
    why << "was built against marsyn plugin API version " << (m ? m->api_version : 0u)
        << ", but this marsyn uses API version " << MARSYN_PLUGIN_API_VERSION
        << "; rebuild the plugin against this marsyn";
    problems_.push_back({file, why.str(), explicit_path});
    return;
  }
  if (m->manifest_size != sizeof(marsyn_plugin_manifest)) {
    problems_.push_back({file, "has a manifest of unexpected size (built with another compiler ABI?)", explicit_path});
    return;
  }
  for (std::size_t i = 0; i < m->entry_count; ++i) {
    const marsyn_plugin_entry& e = m->entries[i];
    if (find(e.kind, e.name)) {
      problems_.push_back({file, std::string("provides ") + e.kind + " '" + e.name +
                                     "', shadowed by an earlier library on the search path",
                           false});
      continue;
    }
    infos_.push_back({e.kind, e.name, e.summary ? e.summary : "", file, e.param_specs ? e.param_specs() : std::vector<ParamSpec>{}});
    entries_.push_back({lib, &e});
  }
}

const PluginInfo* PluginRegistry::find(const std::string& kind, const std::string& name) const {
  for (const auto& i : infos_)
    if (i.kind == kind && i.name == name) return &i;
  return nullptr;
}

std::vector<std::string> PluginRegistry::names(const std::string& kind) const {
  std::vector<std::string> out;
  for (const auto& i : infos_)
    if (i.kind == kind) out.push_back(i.name);
  return out;
}

void* PluginRegistry::create_raw(const std::string& kind, const std::string& name, const Params& params,
                                 std::shared_ptr<void>& library) const {
  for (std::size_t i = 0; i < infos_.size(); ++i) {
    if (infos_[i].kind == kind && infos_[i].name == name) {
      library = entries_[i].library;
      return entries_[i].entry->create(params);
    }
  }
  throw std::out_of_range("no " + kind + " plugin named '" + name + "'");
}

}  // namespace marsyn
