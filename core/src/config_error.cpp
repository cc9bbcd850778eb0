#include "marsyn/core/config_error.hpp"

namespace marsyn {
namespace {
std::string format(const std::string& file, int line, int column, const std::string& path,
                   const std::string& message) {
  std::string s = file;
  if (line > 0) s += ":" + std::to_string(line) + ":" + std::to_string(column);
  s += ": ";
  if (!path.empty()) s += path + ": ";
  return s + message;
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
