#include "yaml_reader.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <sstream>

namespace marsyn::yaml {

Field::Field(YAML::Node node, std::string file, std::string path, YAML::Mark parent_mark)
    : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)), parent_mark_(parent_mark) {}

YAML::Mark Field::mark() const {
  if (defined() && node_.Mark().line >= 0) return node_.Mark();
  return parent_mark_;
}

void Field::fail(const std::string& message) const {
  const YAML::Mark m = mark();
  throw ConfigError(file_, m.line >= 0 ? m.line + 1 : 0, m.column >= 0 ? m.column + 1 : 0, path_, message);
}

Field Field::child(const std::string& key) const {
  const std::string p = path_.empty() ? key : path_ + "." + key;
  if (!is_map()) return Field(YAML::Node(YAML::NodeType::Undefined), file_, p, mark());
  const YAML::Node& cn = node_;  // const access never inserts into the mapping
  return Field(cn[key], file_, p, mark());
}

Field Field::required(const std::string& key) const {
  expect_map();
  Field f = child(key);
  if (!f.present()) {
    Field where(node_, file_, path_, mark());
    where.fail("missing required field '" + key + "'");
  }
  return f;
}

void Field::expect_map() const {
  if (!is_map()) fail("expected a mapping (key: value pairs)");
}

std::vector<std::string> Field::keys() const {
  std::vector<std::string> out;
  if (is_map())
    for (const auto& kv : node_) out.push_back(kv.first.as<std::string>());
  return out;
}

void Field::allow_only(const std::vector<std::string>& allowed) const {
  if (!is_map()) return;
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    bool ok = false;
    for (const auto& a : allowed) ok = ok || a == key;
    if (ok) continue;
    const std::string p = path_.empty() ? key : path_ + "." + key;
    Field f(kv.first, file_, p, mark());
    std::string msg = "unknown field '" + key + "'";
    const std::string near = nearest(key, allowed);
    if (!near.empty()) msg += " (did you mean '" + near + "'?)";
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    f.fail(msg + "; allowed here: " + list);
  }
}

std::size_t Field::size() const { return is_sequence() ? node_.size() : 0; }

Field Field::operator[](std::size_t i) const {
  const YAML::Node& cn = node_;
  return Field(cn[i], file_, path_ + "[" + std::to_string(i) + "]", mark());
}

std::vector<Field> Field::items() const {
  if (!is_sequence()) fail("expected a list");
  std::vector<Field> out;
  for (std::size_t i = 0; i < node_.size(); ++i) out.push_back((*this)[i]);
  return out;
}

double Field::real() const {
  if (!present()) fail("missing value: expected a number");
  if (!is_scalar()) fail("expected a number");
  double v = 0;
  try {
    v = node_.as<double>();
  } catch (const YAML::Exception&) {
    fail("expected a number, got '" + node_.Scalar() + "'");
  }
  if (!std::isfinite(v)) fail("expected a finite number, got '" + node_.Scalar() + "'");
  return v;
}

double Field::positive() const {
  const double v = real();
  if (!(v > 0)) fail("expected a positive number, got " + node_.Scalar());
  return v;
}

double Field::non_negative() const {
  const double v = real();
  if (!(v >= 0)) fail("expected a non-negative number, got " + node_.Scalar());
  return v;
}

long Field::integer() const {
  if (!present() || !is_scalar()) fail("expected an integer");
  try {
    return node_.as<long>();
  } catch (const YAML::Exception&) {
    fail("expected an integer, got '" + node_.Scalar() + "'");
  }
}

long Field::positive_integer() const {
  const long v = integer();
  if (v <= 0) fail("expected a positive integer, got " + std::to_string(v));
  return v;
}

long Field::integer_in(long lo, long hi, const std::string& why) const {
  if (!present() || !is_scalar()) fail("expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  long v = 0;
  try {
    v = node_.as<long>();
  } catch (const YAML::Exception&) {
    fail("expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" + node_.Scalar() + "'" +
         (why.empty() ? "" : " (" + why + ")"));
  }
  if (lo == 1 && v < lo) fail("expected a positive integer (at most " + std::to_string(hi) + "), got " + std::to_string(v));
  if (v < lo || v > hi)
    fail("expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + std::to_string(v) +
         (why.empty() ? "" : " (" + why + ")"));
  return v;
}

bool Field::boolean() const {
  if (!present() || !is_scalar()) fail("expected true or false");
  try {
    return node_.as<bool>();
  } catch (const YAML::Exception&) {
    fail("expected true or false, got '" + node_.Scalar() + "'");
  }
}

std::string Field::text() const {
  if (!present() || !is_scalar()) fail("expected a string");
  return node_.Scalar();
}

Eigen::VectorXd Field::vector(int expected, const std::string& why) const {
  if (!present()) fail("missing value: expected a list of numbers");
  if (!is_sequence()) fail("expected a list of numbers like [1, 2, 3]");
  if (expected >= 0 && static_cast<int>(node_.size()) != expected)
    fail("expected " + std::to_string(expected) + " numbers (" + why + "), got " + std::to_string(node_.size()));
  Eigen::VectorXd v(node_.size());
  for (std::size_t i = 0; i < node_.size(); ++i) v[static_cast<Eigen::Index>(i)] = (*this)[i].real();
  return v;
}

Eigen::VectorXd Field::positive_vector(int expected, const std::string& why) const {
  Eigen::VectorXd v = vector(expected, why);
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (!(v[i] > 0)) (*this)[static_cast<std::size_t>(i)].fail("expected a positive number, got " + node_[i].Scalar());
  return v;
}

Eigen::VectorXd Field::non_negative_vector(int expected, const std::string& why) const {
  Eigen::VectorXd v = vector(expected, why);
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (!(v[i] >= 0)) (*this)[static_cast<std::size_t>(i)].fail("expected a non-negative number, got " + node_[i].Scalar());
  return v;
}


namespace {
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}
}  // namespace

std::string nearest(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = 3;  // suggest only close matches
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

}  // namespace marsyn::yaml
