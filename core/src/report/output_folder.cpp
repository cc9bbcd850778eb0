#include "marsyn/core/report/output_folder.hpp"

#include "marsyn/core/problem/config_error.hpp"

namespace fs = std::filesystem;

namespace marsyn {

OutputFolder::OutputFolder(const std::string& dir) : requested_(dir) {
  if (dir.empty()) throw ConfigError("command line", 0, 0, "--out", "expected an output folder, got an empty path");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw ConfigError(dir, 0, 0, "--out",
                      "cannot create the output folder" + (ec ? " (" + ec.message() + ")" : std::string(" (not a directory)")));
  resolved_ = fs::weakly_canonical(fs::absolute(dir), ec);
  if (ec) throw ConfigError(dir, 0, 0, "--out", "cannot resolve the output folder (" + ec.message() + ")");
}

std::string OutputFolder::path(const std::string& file) const {
  const fs::path f(file);
  const bool plain = !file.empty() && f.is_relative() && !f.has_parent_path() && file != "." && file != ".." &&
                     file.find('/') == std::string::npos && file.find('\0') == std::string::npos;
  if (!plain)
    throw ConfigError(requested_, 0, 0, "--out",
                      "refusing to write '" + file + "': an output file must be a plain name inside the output folder");
  std::error_code ec;
  // weakly_canonical stops at the first missing component, so a dangling link would pass as
  // a plain new file (and the write would create its target): refuse those outright.
  if (fs::is_symlink(fs::symlink_status(resolved_ / f, ec)) && !fs::exists(resolved_ / f, ec))
    throw ConfigError(requested_, 0, 0, "--out",
                      "refusing to write '" + file + "': it is a symbolic link to " +
                          fs::read_symlink(resolved_ / f, ec).string() + ", which does not exist");
  const fs::path resolved = fs::weakly_canonical(resolved_ / f, ec);
  if (ec || resolved.parent_path() != resolved_)
    throw ConfigError(requested_, 0, 0, "--out",
                      "refusing to write '" + file + "': it resolves to " + resolved.string() + ", outside the output folder " +
                          resolved_.string() + " (a symbolic link?)");
  return (resolved_ / f).string();
}

}  // namespace marsyn
