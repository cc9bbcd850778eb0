#pragma once
// Lists as the loader's messages print them; numbers print as everywhere else (number_text).
#include <string>
#include <vector>

#include "marsyn/number_text.hpp"

namespace marsyn::loader {

inline std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& i : items) out += (out.empty() ? "" : ", ") + i;
  return out.empty() ? "(none found)" : out;
}

}  // namespace marsyn::loader
