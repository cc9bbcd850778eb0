#pragma once
// The pendulum example (examples/pendulum.yaml) rewritten for a core test: its `tracker` line
// replaced by `tracker_line`, the test tracker's folder (tests/fixtures/never_tracker.cpp) on
// plugin_paths, and each `edits` pair (text, replacement) applied once. Written to a temporary
// folder as <name>.yaml; returns its path.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "temp_dir.hpp"

namespace marsyn::test {

inline std::string pendulum_variant(const std::string& name, const std::string& tracker_line,
                                    const std::vector<std::pair<std::string, std::string>>& edits = {}) {
  namespace fs = std::filesystem;
  std::ifstream in(std::string(MARSYN_SOURCE_DIR) + "/examples/pendulum.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  s.replace(s.find("tracker: abcd\n"), 14, tracker_line + "\nplugin_paths: [" + NEVER_TRACKER_DIR + "]\n");
  for (const auto& [from, to] : edits) {
    const auto at = s.find(from);
    if (at == std::string::npos) throw std::logic_error("pendulum.yaml has no '" + from + "'");
    s.replace(at, from.size(), to);
  }
  const fs::path p = process_temp_dir("marsyn_pendulum_") / (name + ".yaml");
  std::ofstream(p) << s;
  return p.string();
}

}  // namespace marsyn::test
