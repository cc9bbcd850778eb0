// yaml::load_file: reading a problem file safely (size, file kind, NUL bytes, parser progress,
// duplicate and complex keys, alias expansion) before any field is looked at.
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
// `open` holds the nodes being walked, outermost first: yaml-cpp resolves an alias inside its own
// anchor ('a: &a [x, *a]') to the enclosing node itself, a cycle that any recursive walk (this one,
// or the loader's) would follow until the stack runs out.
void check_tree(const YAML::Node& node, const std::string& file, const std::string& path, long& budget,
                std::vector<YAML::Node>& open) {
  for (const auto& o : open)
    if (o.is(node)) {
      const YAML::Mark m = node.Mark();
      throw ConfigError(file, m.line + 1, m.column + 1, path,
                        "an alias that contains itself (its anchor '&' encloses the '*'); a problem file "
                        "cannot be a cycle");
    }
  if (--budget < 0) {
    const YAML::Mark m = node.Mark();
    throw ConfigError(file, m.line + 1, m.column + 1, path,
                      "the document expands to more than " + std::to_string(kMaxYamlNodes) +
                          " YAML nodes (aliases repeating large parts?); a problem file is far smaller");
  }
  if (!node.IsMap() && !node.IsSequence()) return;
  open.push_back(node);
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
      check_tree(kv.second, file, key_path(path, key), budget, open);
    }
  } else if (node.IsSequence()) {
    std::size_t i = 0;
    for (const auto& item : node) check_tree(item, file, path + "[" + std::to_string(i++) + "]", budget, open);
  }
  open.pop_back();
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
    std::vector<YAML::Node> open;
    check_tree(docs[0], file, "", budget, open);
  } catch (const YAML::Exception& e) {
    throw ConfigError(file, e.mark.line + 1, e.mark.column + 1, "", std::string("malformed YAML: ") + e.msg);
  }
  return docs[0];
}

}  // namespace marsyn::yaml
