#pragma once
// Typed, located access to a YAML document: every value read knows its file, line, column and
// field path (agents[3].eta_x), so every rejection can say exactly where and what was expected.
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "marsyn/core/problem/config_error.hpp"

namespace marsyn::yaml {

class Field {
 public:
  Field(YAML::Node node, std::string file, std::string path, YAML::Mark parent_mark = YAML::Mark());

  bool present() const { return defined() && !node_.IsNull(); }
  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }
  const YAML::Node& node() const { return node_; }

  [[noreturn]] void fail(const std::string& message) const;

  // Mapping access. child() of a missing key is a Field that is not present().
  Field child(const std::string& key) const;
  Field required(const std::string& key) const;  // fails when missing
  void expect_map() const;
  bool is_map() const { return defined() && node_.IsMap(); }
  bool is_sequence() const { return defined() && node_.IsSequence(); }
  bool is_scalar() const { return defined() && node_.IsScalar(); }
  // Rejects keys not in `allowed`, suggesting the nearest allowed key for typos.
  void allow_only(const std::vector<std::string>& allowed) const;
  std::vector<std::string> keys() const;

  // Sequence access.
  std::size_t size() const;
  Field operator[](std::size_t i) const;
  std::vector<Field> items() const;

  // Scalars.
  double real() const;                  // finite number
  double positive() const;              // finite and > 0
  double non_negative() const;          // finite and >= 0
  long integer() const;
  long positive_integer() const;
  // An integer in [lo, hi]; `why` explains the bound ("at most 1000 substeps").
  long integer_in(long lo, long hi, const std::string& why) const;
  bool boolean() const;
  std::string text() const;
  bool is_null_scalar() const { return defined() && node_.IsNull(); }

  // Vectors of finite numbers; `expected` is the required length (-1: any), `why` explains the
  // length ("the dynamics 'unicycle' has 3 states").
  Eigen::VectorXd vector(int expected, const std::string& why) const;
  Eigen::VectorXd positive_vector(int expected, const std::string& why) const;
  Eigen::VectorXd non_negative_vector(int expected, const std::string& why) const;

 private:
  // yaml-cpp throws on most calls to a node that a lookup did not find; everything asks this first.
  bool defined() const { return node_.IsDefined(); }
  YAML::Mark mark() const;
  YAML::Node node_;
  std::string file_, path_;
  YAML::Mark parent_mark_;
};

// Limits of the format (docs/problem-format.md, "Checks"): bytes of a problem file, and YAML
// nodes after alias expansion.
inline constexpr std::uintmax_t kMaxConfigBytes = 16u << 20;
inline constexpr long kMaxYamlNodes = 500'000;

// Parses a file: exactly one YAML document, at most kMaxConfigBytes, a regular file, no NUL bytes,
// no duplicate or complex mapping keys. Every failure (unreadable, a directory or device, syntax,
// nesting too deep) becomes a ConfigError naming the file and, where known, line and column.
YAML::Node load_file(const std::string& file);

std::string nearest(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace marsyn::yaml
