#pragma once
// The loader's message for a bad file, or "" when it loads (tests of located errors).
#include <exception>
#include <string>

#include "marsyn/core/problem/problem_loader.hpp"

namespace marsyn::test {

inline std::string load_error(const std::string& path) {
  try {
    load_problem(path);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace marsyn::test
