#pragma once
// A test process's scratch folder in the system's temp folder, removed when the process exits
// (ctest runs each test as a process of its own: thousands of folders were left in /tmp).
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace marsyn::test {

// temp/<prefix><pid>, made on first use.
inline std::filesystem::path process_temp_dir(const std::string& prefix) {
  namespace fs = std::filesystem;
  struct RemovedAtExit {
    std::vector<fs::path> dirs;
    ~RemovedAtExit() {
      std::error_code ec;
      for (const fs::path& d : dirs) fs::remove_all(d, ec);
    }
  };
  static RemovedAtExit made;
  const fs::path dir = fs::temp_directory_path() / (prefix + std::to_string(::getpid()));
  if (std::find(made.dirs.begin(), made.dirs.end(), dir) == made.dirs.end()) made.dirs.push_back(dir);
  fs::create_directories(dir);
  return dir;
}

}  // namespace marsyn::test
