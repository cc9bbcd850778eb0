#include "yaml_reader.hpp"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>

#include <climits>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

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

// Reads at most `limit` + 1 bytes, after refusing what is not a regular file: a directory, a
// device such as /dev/zero, a pipe or a socket would otherwise be read until memory runs out or
// misreported as an empty file.
std::string read_limited(const std::string& file, std::uintmax_t limit) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (ec || !fs::exists(st)) throw ConfigError(file, 0, 0, "", "cannot read the file (missing or unreadable)");
  if (fs::is_directory(st)) throw ConfigError(file, 0, 0, "", "is a directory; expected a YAML problem file");
  if (!fs::is_regular_file(st))
    throw ConfigError(file, 0, 0, "", "is not a regular file (a device, pipe or socket); expected a YAML problem file");
  const std::uintmax_t size = fs::file_size(file, ec);
  auto too_big = [&](const std::string& what) {
    return ConfigError(file, 0, 0, "",
                       "the file is " + what + " bytes; a problem file may have at most " + std::to_string(limit) +
                           " bytes (" + std::to_string(limit >> 20) + " MiB)");
  };
  if (!ec && size > limit) throw too_big(std::to_string(size));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ConfigError(file, 0, 0, "", "cannot read the file (missing or unreadable)");
  std::string text;
  char buf[65536];
  while (in) {
    in.read(buf, sizeof buf);
    text.append(buf, static_cast<std::size_t>(in.gcount()));
    if (text.size() > limit) throw too_big("more than " + std::to_string(limit));
  }
  if (in.bad()) throw ConfigError(file, 0, 0, "", "cannot read the file (a read error)");
  return text;
}

// Line and column (1-based) of byte `pos` of `text`.
std::pair<int, int> position(const std::string& text, std::size_t pos) {
  int line = 1, col = 1;
  for (std::size_t i = 0; i < pos && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return {line, col};
}

// yaml-cpp 0.7 never returns from some malformed input: a ',' outside a flow collection (a file
// holding just ",") makes its parser emit null nodes forever, allocating until memory runs out
// (found by fuzz/problem_loader_fuzzer). A first pass over the parser's events with a budget
// proportional to the text turns that into a located error; a well-formed file produces far fewer
// events than it has bytes.
struct ParserStuck {
  YAML::Mark mark;
};

class EventBudget : public YAML::EventHandler {
 public:
  explicit EventBudget(long budget) : left_(budget) {}
  void OnDocumentStart(const YAML::Mark& m) override { tick(m); }
  void OnDocumentEnd() override { tick(last_); }
  void OnNull(const YAML::Mark& m, YAML::anchor_t) override { tick(m); }
  void OnAlias(const YAML::Mark& m, YAML::anchor_t) override { tick(m); }
  void OnScalar(const YAML::Mark& m, const std::string&, YAML::anchor_t, const std::string&) override { tick(m); }
  void OnSequenceStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    tick(m);
  }
  void OnSequenceEnd() override { tick(last_); }
  void OnMapStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    tick(m);
  }
  void OnMapEnd() override { tick(last_); }

 private:
  void tick(const YAML::Mark& m) {
    last_ = m;
    if (--left_ < 0) throw ParserStuck{m};
  }
  long left_;
  YAML::Mark last_;
};

void check_parser_progress(const std::string& text, const std::string& file) {
  std::istringstream in(text);
  YAML::Parser parser(in);
  EventBudget budget(4 * static_cast<long>(text.size()) + 64);
  try {
    while (parser.HandleNextDocument(budget)) {
    }
  } catch (const ParserStuck& e) {
    throw ConfigError(file, e.mark.line >= 0 ? e.mark.line + 1 : 0, e.mark.column >= 0 ? e.mark.column + 1 : 0, "",
                      "YAML syntax error: the parser makes no progress here (a ',' outside [...] or {...}?)");
  }
}

std::string key_path(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

// yaml-cpp 0.7 keeps the first of two equal keys silently and turns a complex key into an
// exception far from the file; walking the tree once after parsing rejects both with the key's
// location. `budget` bounds the walk: aliases can make a small file expand exponentially.
void check_tree(const YAML::Node& node, const std::string& file, const std::string& path, long& budget) {
  if (--budget < 0) {
    const YAML::Mark m = node.Mark();
    throw ConfigError(file, m.line + 1, m.column + 1, path,
                      "the document expands to more than " + std::to_string(kMaxYamlNodes) +
                          " YAML nodes (aliases repeating large parts?); a problem file is far smaller");
  }
  if (node.IsMap()) {
    std::vector<std::pair<std::string, YAML::Mark>> seen;
    for (const auto& kv : node) {
      const YAML::Mark km = kv.first.Mark();
      if (!kv.first.IsScalar())
        throw ConfigError(file, km.line + 1, km.column + 1, path,
                          std::string("expected a plain name as the mapping key, got a ") +
                              (kv.first.IsMap() ? "mapping" : kv.first.IsSequence() ? "list" : "null") +
                              " (complex keys '? ...' are not part of the format)");
      const std::string key = kv.first.Scalar();
      for (const auto& [k, m] : seen)
        if (k == key)
          throw ConfigError(file, km.line + 1, km.column + 1, key_path(path, key),
                            "duplicate key '" + key + "' (first given at line " + std::to_string(m.line + 1) +
                                ", column " + std::to_string(m.column + 1) + "); give each key once");
      seen.emplace_back(key, km);
      check_tree(kv.second, file, key_path(path, key), budget);
    }
  } else if (node.IsSequence()) {
    std::size_t i = 0;
    for (const auto& item : node) check_tree(item, file, path + "[" + std::to_string(i++) + "]", budget);
  }
}

}  // namespace

YAML::Node load_file(const std::string& file) {
  const std::string text = read_limited(file, kMaxConfigBytes);
  if (const auto nul = text.find('\0'); nul != std::string::npos) {
    const auto [line, col] = position(text, nul);
    throw ConfigError(file, line, col, "", "the file contains a NUL byte: a binary file, not a YAML problem file");
  }
  std::vector<YAML::Node> docs;
  try {
    check_parser_progress(text, file);
    docs = YAML::LoadAll(text);
  } catch (const ConfigError&) {
    throw;
  } catch (const YAML::DeepRecursion& e) {
    throw ConfigError(file, e.mark.line + 1, e.mark.column + 1, "",
                      "nesting deeper than " + std::to_string(e.depth()) +
                          " levels of lists or mappings; a problem file needs only a few");
  } catch (const YAML::Exception& e) {
    if (e.mark.line >= 0) throw ConfigError(file, e.mark.line + 1, e.mark.column + 1, "", "YAML syntax error: " + e.msg);
    throw ConfigError(file, 0, 0, "", "YAML syntax error: " + e.msg);
  } catch (const std::exception& e) {
    throw ConfigError(file, 0, 0, "", std::string("the file could not be parsed as YAML: ") + e.what());
  }
  if (docs.size() > 1) {
    // The second document's start: its node's mark, or for an empty document the '---' line.
    YAML::Mark m = docs[1].Mark();
    int line = m.line >= 0 ? m.line + 1 : 0, col = m.column >= 0 ? m.column + 1 : 0;
    if (line == 0) {
      std::size_t at = text.rfind("\n---"), first = text.find("\n---");
      if (text.rfind("---", 0) == 0 && first != std::string::npos) at = first;
      if (at != std::string::npos) std::tie(line, col) = position(text, at + 1);
    }
    throw ConfigError(file, line, col, "",
                      "a second YAML document (after '---' or '...'); a problem file holds exactly one document");
  }
  if (docs.empty() || !docs[0].IsDefined() || docs[0].IsNull()) throw ConfigError(file, 0, 0, "", "the file is empty");
  long budget = kMaxYamlNodes;
  try {
    check_tree(docs[0], file, "", budget);
  } catch (const YAML::Exception& e) {
    throw ConfigError(file, e.mark.line + 1, e.mark.column + 1, "", std::string("malformed YAML: ") + e.msg);
  }
  return docs[0];
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
