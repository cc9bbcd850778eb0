#pragma once
// A problem file with some of its text replaced, written to the test's temporary folder: the
// tests that vary one field of a shipped problem share it.
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace marsyn::test {

// `base` with each (from, to) replaced (the first occurrence; a missing one throws), written as
// <TempDir>/<tag>.yaml; returns its path.
inline std::string problem_variant(const std::string& base, const std::vector<std::pair<std::string, std::string>>& edits,
                                   const std::string& tag) {
  std::ifstream in(base);
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  for (const auto& [from, to] : edits) {
    const auto at = s.find(from);
    if (at == std::string::npos) throw std::runtime_error("no '" + from + "' in " + base);
    s.replace(at, from.size(), to);
  }
  const std::string path = ::testing::TempDir() + tag + ".yaml";
  std::ofstream(path) << s;
  return path;
}

}  // namespace marsyn::test
