#pragma once
// The one place output file paths are made: every file marsyn writes is a plain name inside the
// output folder, checked after path resolution (symbolic links followed, std::filesystem::
// weakly_canonical) to lie directly in it. Names reach here already restricted by the loader
// (input_limits.hpp); this is the second line: a link planted in the folder, or a name that
// slipped through, is refused before anything is opened.
#include <filesystem>
#include <string>

namespace marsyn {

class OutputFolder {
 public:
  // Creates `dir` (and parents) when missing. Throws ConfigError (field --out) when it cannot.
  explicit OutputFolder(const std::string& dir);

  // dir/file, after checking that `file` is one plain component and that the resolved path's
  // parent is the resolved folder. Throws ConfigError otherwise.
  std::string path(const std::string& file) const;
  const std::filesystem::path& dir() const { return resolved_; }
  const std::string& requested() const { return requested_; }

 private:
  std::string requested_;
  std::filesystem::path resolved_;
};

}  // namespace marsyn
