// `marsyn export`: a controller file (or every <agent>.ctrl of a `solve` folder) as C99 or in
// SCOTS' format, through the tracker plugin that wrote it (Controller::export_to). Every failure
// is bad input here (a missing or corrupt file, a bad prefix, an unwritable folder): one line on
// stderr and exit code 2.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>

#include "commands.hpp"
#include "marsyn/c_source.hpp"
#include "marsyn/core/plugins/plugin_registry.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/tracking/tracker_choice.hpp"
#include "marsyn/tracker.hpp"

namespace fs = std::filesystem;

namespace marsyn::cli {
namespace {

int fail(const std::string& what) {
  std::cerr << "error: " << what << "\n";
  return 2;
}

// The tracker that wrote `file` (<agent>.ctrl) as the result.json beside it records it; empty
// when there is no such record.
std::string tracker_from_result(const fs::path& file) {
  const auto recorded = recorded_trackers(file.parent_path().string());
  const auto it = recorded.find(file.stem().string());
  return it == recorded.end() ? std::string() : it->second;
}

// The controller files the inputs name, a folder's *.ctrl sorted by name; "" or what is wrong.
std::string collect_files(const std::vector<std::string>& inputs, std::vector<std::string>& files) {
  for (const auto& in : inputs) {
    std::error_code ec;
    if (fs::is_directory(in, ec)) {
      std::vector<std::string> found;
      for (const auto& e : fs::directory_iterator(in, ec))
        if (e.path().extension() == ".ctrl") found.push_back(e.path().string());
      if (found.empty()) return in + ": a folder without controller files (*.ctrl)";
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else if (fs::exists(in, ec)) {
      files.push_back(in);
    } else {
      return "cannot open controller file " + in + " (no such file or folder)";
    }
  }
  return {};
}

// The tracker plugins that read the files, each created once.
class Readers {
 public:
  explicit Readers(std::string tracker_name) : tracker_name_(std::move(tracker_name)) {}

  // The tracker named for `file`: --tracker, else the one result.json records for it; nullptr
  // without `error` when neither names one (read() then asks every installed tracker).
  std::shared_ptr<Tracker> tracker_for(const std::string& file, std::string* error) {
    const std::string recorded = tracker_name_.empty() ? tracker_from_result(file) : std::string();
    const std::string name = tracker_name_.empty() ? recorded : tracker_name_;
    if (name.empty()) return nullptr;
    try {
      return created(name);
    } catch (const std::exception&) {
      std::string names;
      for (const auto& n : registry_.names("tracker")) names += (names.empty() ? "" : ", ") + n;
      *error = (recorded.empty() ? "--tracker: " : file + ": written by the tracker '" + recorded + "' (result.json); ") +
               "no tracker plugin named '" + name + "' (found: " + (names.empty() ? "none" : names) + ")";
      return nullptr;
    }
  }

  // The controller in `file`, or nullptr with `error`. A file no tracker is named for (one written
  // by `marsyn track`, with no result.json beside it) says itself which tracker wrote it: each
  // reader checks its own magic, so every installed tracker is asked in turn.
  std::shared_ptr<const Controller> read(const std::string& file, std::string* error) {
    error->clear();
    if (const auto tracker = tracker_for(file, error)) {
      try {
        return tracker->read_controller(file);
      } catch (const std::exception& e) {
        *error = e.what();
        return nullptr;
      }
    }
    if (!error->empty()) return nullptr;
    std::string first_reason;
    for (const auto& name : registry_.names("tracker")) {
      try {
        return created(name)->read_controller(file);
      } catch (const std::exception& e) {  // not this tracker's file
        if (first_reason.empty()) first_reason = e.what();
      }
    }
    *error = first_reason.empty() ? file + ": no tracker plugin is installed to read it" : first_reason;
    return nullptr;
  }

 private:
  std::shared_ptr<Tracker> created(const std::string& name) {  // throws for an unknown name
    if (auto it = trackers_.find(name); it != trackers_.end()) return it->second;
    return trackers_[name] = registry_.create<Tracker>(name);
  }

  std::string tracker_name_;
  PluginRegistry registry_;
  std::map<std::string, std::shared_ptr<Tracker>> trackers_;
};

}  // namespace

int run_export(const std::vector<std::string>& inputs, const std::string& format, const std::string& out_dir,
               const std::string& prefix, const std::string& encoding, const std::string& tracker_name) {
  if (format != "c" && format != "scs") return fail("--format: unknown format '" + format + "'; expected c or scs");
  if (encoding != "auto" && encoding != "dense" && encoding != "rle")
    return fail("--encoding: unknown encoding '" + encoding + "'; expected auto, dense or rle");
  if (!prefix.empty() && !c_source::is_c_identifier(prefix))
    return fail("--prefix: '" + prefix + "' is not a C identifier ([A-Za-z_][A-Za-z0-9_]*)");

  std::vector<std::string> files;
  if (const std::string why = collect_files(inputs, files); !why.empty()) return fail(why);
  if (!prefix.empty() && files.size() > 1)
    return fail("--prefix names one controller's symbols; " + std::to_string(files.size()) + " controllers given");

  Readers readers(tracker_name);
  if (!tracker_name.empty()) {
    std::string error;
    if (!readers.tracker_for(files.empty() ? std::string() : files.front(), &error)) return fail(error);
  }
  const std::string dir = out_dir.empty() ? "." : out_dir;
  long long total = 0;
  std::set<fs::path> written;
  for (const auto& file : files) {
    std::string error;
    const std::shared_ptr<const Controller> ctrl = readers.read(file, &error);
    if (!ctrl) return fail(error);
    ExportRequest req;
    req.format = format;
    req.out_dir = dir;
    req.prefix = prefix;
    req.encoding = encoding;
    req.source = fs::path(file).filename().string();
    const ExportResult r = ctrl->export_to(req);
    if (!r.ok) return fail(file + ": " + r.message);
    for (const auto& f : r.files)
      if (!written.insert(fs::weakly_canonical(f)).second)
        return fail(file + ": writes " + f + " again (two agents' names give the same prefix); export them one by one with --prefix");
    std::printf("%s\n", r.message.c_str());
    for (const auto& f : r.files) std::printf("  wrote %s\n", f.c_str());
    total += r.const_data_bytes;
  }
  if (format == "c")
    std::printf("const data (flash) %lld bytes in %zu controller%s, plus the lookup code (docs/deploy.md)\n", total,
                files.size(), files.size() == 1 ? "" : "s");
  return 0;
}

}  // namespace marsyn::cli
