#include "marsyn/core/problem/config_error.hpp"

#include <cstdio>

namespace marsyn {

std::string printable(const std::string& text, std::size_t max_chars) {
  std::string out;
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  auto hex = [&](unsigned char c) {
    char buf[5];
    std::snprintf(buf, sizeof buf, "\\x%02X", c);
    out += buf;
  };
  for (std::size_t i = 0; i < n;) {
    if (out.size() >= max_chars) {
      out += "...";
      break;
    }
    const unsigned char c = s[i];
    if (c == '\n') { out += "\\n"; ++i; continue; }
    if (c == '\t') { out += "\\t"; ++i; continue; }
    if (c == '\r') { out += "\\r"; ++i; continue; }
    if (c < 0x20 || c == 0x7F) { hex(c); ++i; continue; }
    if (c < 0x80) { out += static_cast<char>(c); ++i; continue; }
    // A well-formed UTF-8 sequence (no overlongs, no surrogates, <= U+10FFFF) is kept as is.
    int len = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
    bool ok = len > 0 && i + len <= n;
    for (int k = 1; ok && k < len; ++k) ok = (s[i + k] & 0xC0) == 0x80;
    if (ok && len == 3) {
      if (c == 0xE0 && s[i + 1] < 0xA0) ok = false;
      if (c == 0xED && s[i + 1] >= 0xA0) ok = false;
    }
    if (ok && len == 4) {
      if (c == 0xF0 && s[i + 1] < 0x90) ok = false;
      if (c == 0xF4 && s[i + 1] >= 0x90) ok = false;
    }
    if (!ok) { hex(c); ++i; continue; }
    out.append(text, i, static_cast<std::size_t>(len));
    i += static_cast<std::size_t>(len);
  }
  return out;
}

namespace {
std::string format(const std::string& file, int line, int column, const std::string& path,
                   const std::string& message) {
  std::string s = printable(file, 1024);
  if (line > 0) s += ":" + std::to_string(line) + ":" + std::to_string(column);
  s += ": ";
  if (!path.empty()) s += printable(path, 512) + ": ";
  return s + printable(message);
}
}  // namespace

ConfigError::ConfigError(std::string file, int line, int column, std::string path, std::string message)
    : std::runtime_error(format(file, line, column, path, message)),
      file_(std::move(file)),
      path_(std::move(path)),
      message_(std::move(message)),
      line_(line),
      column_(column) {}

}  // namespace marsyn
