#pragma once
// The one exception type that reaches the CLI boundary for bad input: it names the file, the
// line and column, the field path (e.g. agents[3].eta_x) and what was expected. The CLI prints
// what() and exits with code 2. what() never carries raw control bytes or malformed UTF-8:
// they are escaped (\n, \xFF), so a binary file or a hostile name cannot garble the terminal.
#include <cstddef>
#include <stdexcept>
#include <string>

namespace marsyn {

// `text` with control characters, DEL and bytes that are not well-formed UTF-8 escaped (\n, \t,
// \xNN), cut after about max_chars characters ("..."): safe to print on one terminal line.
std::string printable(const std::string& text, std::size_t max_chars = 4096);

class ConfigError : public std::runtime_error {
 public:
  ConfigError(std::string file, int line, int column, std::string path, std::string message);

  const std::string& file() const noexcept { return file_; }
  int line() const noexcept { return line_; }  // 1-based, 0 when unknown
  int column() const noexcept { return column_; }
  const std::string& path() const noexcept { return path_; }
  const std::string& message() const noexcept { return message_; }

 private:
  std::string file_, path_, message_;
  int line_, column_;
};

}  // namespace marsyn
