#pragma once
// Numbers as messages, summaries and tables print them, in core and in plugins alike.
#include <Eigen/Core>
#include <cstdio>
#include <string>

namespace marsyn {

// printf's %g with `digits` significant digits: "0.25", "1e+06", "4096". Six digits is what an
// ostream prints by default, so messages that used `os << v` read the same.
inline std::string number_text(double v, int digits = 6) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

// printf's %a, "0x1.999999999999ap-4": the very same double, as C99 and strtod read it back.
inline std::string hex_double(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", v);
  return buf;
}

// "(a, b, c)", each coordinate by number_text with `digits`; `open`, `close` and `sep` give other
// brackets and separators ("(a,b,c)": one token in a key=value log line).
inline std::string list_text(const Eigen::VectorXd& v, const char* open = "(", const char* close = ")",
                             const char* sep = ", ", int digits = 6) {
  std::string s = open;
  for (Eigen::Index i = 0; i < v.size(); ++i) s += (i ? sep : "") + number_text(v[i], digits);
  return s + close;
}

}  // namespace marsyn
