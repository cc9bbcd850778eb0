#pragma once
// Numbers as messages, summaries and tables print them, in core and in plugins alike.
#include <Eigen/Core>
#include <cstdio>
#include <string>

namespace marsyn {

// The most significant digits a message prints (docs/messages.md): it reads 3, and 4 where two
// figures compared agree in the third ("half-width 0.2012 vs eps 0.2"). number_text's default and
// the precision of every message stream. Files that are read back keep full precision elsewhere.
inline constexpr int kMessageDigits = 4;

// printf's %g with `digits` significant digits: "0.25", "1e+06", "4096".
// Whole-number magnitudes up to 1e9 keep their integer digits ("38910 tube cells", not
// "3.891e+04").
inline std::string number_text(double v, int digits = kMessageDigits) {
  char buf[64];
  const double a = v < 0 ? -v : v;
  double big = 1;
  for (int i = 0; i < digits; ++i) big *= 10;
  if (a >= big && a < 1e9)
    std::snprintf(buf, sizeof buf, "%.0f", v);
  else
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
                             const char* sep = ", ", int digits = kMessageDigits) {
  std::string s = open;
  for (Eigen::Index i = 0; i < v.size(); ++i) s += (i ? sep : "") + number_text(v[i], digits);
  return s + close;
}

}  // namespace marsyn
