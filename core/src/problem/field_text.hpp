#pragma once
// Numbers and lists as the loader's messages print them.
#include <sstream>
#include <string>
#include <vector>

namespace marsyn::loader {

inline std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

inline std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& i : items) out += (out.empty() ? "" : ", ") + i;
  return out.empty() ? "(none found)" : out;
}

}  // namespace marsyn::loader
