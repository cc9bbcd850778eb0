#pragma once
// The message style of docs/messages.md as checks over printed lines: what a test can hold every
// error, warning, log line and summary to. Each rule returns why a line breaks it ("" when it
// does not). Text the user wrote (between quotes) and paths are not judged: a message may quote
// a file's "1.50" back.
#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

namespace marsyn::test {

struct StyleBreak {
  std::string rule, why;
};

namespace style_detail {

// The line without the log's clock ("[  100.01 s] ", a fixed-width column), quoted text ('...'
// or "...") and tokens holding a '/' (paths).
inline std::string judged_part(std::string line) {
  if (line.rfind("[", 0) == 0) {
    const auto close = line.find(" s] ");
    if (close != std::string::npos && line.find_first_not_of(" 0123456789.", 1) == close + 1) line = line.substr(close + 4);
  }
  std::string out;
  char quote = 0;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quote) {
      if (c == quote) quote = 0;
      continue;
    }
    // An apostrophe inside a word ("agent's") is not a quote.
    const bool word_before = i > 0 && std::isalnum(static_cast<unsigned char>(line[i - 1]));
    if (c == '"' || (c == '\'' && !word_before)) {
      quote = c;
      out += " QUOTED ";
      continue;
    }
    out += c;
  }
  std::string kept, token;
  auto flush = [&] {
    if (token.find('/') == std::string::npos) {
      kept += token;
    } else {
      for (const char c : token)  // "[track 1/3]": the bracket stays
        if (c == '(' || c == ')' || c == '[' || c == ']') kept += c;
    }
    token.clear();
  };
  for (const char c : out) {
    if (c == ' ' || c == '\t') {
      flush();
      kept += c;
    } else {
      token += c;
    }
  }
  flush();
  return kept;
}

struct Number {
  std::string text;      // as printed
  std::string mantissa;  // the digits before an exponent, '.' included
  int exponent = 0;
  bool decimal = false;  // has a '.'
};

// Decimal numbers standing alone (not part of a name such as "x0", "eta_u2" or "ee582538", nor of
// a version "1.2.3").
inline std::vector<Number> numbers(const std::string& s) {
  std::vector<Number> out;
  std::size_t i = 0;
  auto word = [&](std::size_t k) { return std::isalnum(static_cast<unsigned char>(s[k])) || s[k] == '_'; };
  while (i < s.size()) {
    if (!std::isdigit(static_cast<unsigned char>(s[i])) || (i > 0 && (word(i - 1) || s[i - 1] == '.'))) {
      ++i;
      continue;
    }
    std::size_t j = i;
    Number n;
    while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.')) ++j;
    n.mantissa = s.substr(i, j - i);
    if (j < s.size() && (s[j] == 'e' || s[j] == 'E') && j + 1 < s.size()) {
      std::size_t k = j + 1;
      if (s[k] == '+' || s[k] == '-') ++k;
      std::size_t d = k;
      while (d < s.size() && std::isdigit(static_cast<unsigned char>(s[d]))) ++d;
      if (d > k) {
        n.exponent = std::stoi(s.substr(j + 1, d - j - 1));
        j = d;
      }
    }
    const bool glued = j < s.size() && word(j);
    while (!n.mantissa.empty() && n.mantissa.back() == '.') n.mantissa.pop_back();  // "2." ends a sentence
    const auto dots = std::count(n.mantissa.begin(), n.mantissa.end(), '.');
    n.text = s.substr(i, j - i);
    n.decimal = dots == 1;
    if (!glued && dots <= 1) out.push_back(n);
    i = j;
  }
  return out;
}

inline int significant_digits(const std::string& mantissa) {
  std::string d;
  for (const char c : mantissa)
    if (c != '.') d += c;
  const auto first = d.find_first_not_of('0');
  return first == std::string::npos ? 0 : static_cast<int>(d.size() - first);
}

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

inline std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  const auto e = s.find_last_not_of(" \t\r");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

inline bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace style_detail

// Every rule of docs/messages.md a line breaks (empty: none).
inline std::vector<StyleBreak> style_breaks(const std::string& line) {
  using namespace style_detail;
  std::vector<StyleBreak> out;
  const std::string s = judged_part(line);
  for (const Number& n : numbers(s)) {
    if (n.decimal && significant_digits(n.mantissa) > 4)
      out.push_back({"digits", n.text + " has more than 4 significant digits"});
    const auto dot = n.mantissa.find('.');
    if (n.decimal && n.mantissa.size() - dot > 5 && n.mantissa.back() == '0')
      out.push_back({"fixed-point", n.text + " is std::to_string's or %f's six decimals, not a number_text"});
    if (n.exponent <= -13 && significant_digits(n.mantissa) > 0)
      out.push_back({"rounding", n.text + " is rounding left over: print 0"});
  }
  for (const char* p : {"upper bound of x", "lower bound of x", "bound of u", "variable ", "x[", "u["}) {
    const auto at = s.find(p);
    const std::size_t after = at + std::string(p).size();
    if (at != std::string::npos && after < s.size() && std::isdigit(static_cast<unsigned char>(s[after])))
      out.push_back({"product-index", "'" + std::string(p) + s[after] +
                                          "...' is an index of the planner's vector, not an agent and coordinate"});
  }
  for (const char* p : {"status -", "status 0", "status 1", "status 2", "status 3", "status 4", "status 5", "status 6",
                        "status 7", "status 8", "status 9", "return code", "NLOPT_", "Solve_Succeeded",
                        "Infeasible_Problem", "Maximum_Iterations", "Restoration_Failed"})
    if (contains(s, p)) out.push_back({"raw-status", "'" + std::string(p) + "' is a solver's code, not words"});
  const std::string t = trimmed(s);
  for (const char* tail :
       {" would", " or", " and", " by", " of", " to", " the", " with", " than", ",", " (", " -", " +"})
    if (ends_with(t, tail)) out.push_back({"cut", "the line ends in '" + std::string(tail) + "'"});
  int round = 0, square = 0;
  for (const char c : s) {
    round += c == '(' ? 1 : c == ')' ? -1 : 0;
    square += c == '[' ? 1 : c == ']' ? -1 : 0;
    if (round < 0 || square < 0) break;
  }
  if (round != 0 || square != 0) out.push_back({"cut", "unbalanced brackets"});
  // A value printed as "inf" or "nan" (printf's words for a figure that overflowed or was never
  // set): the line should say what it means ("beyond 1e308", "no enclosure"). A line about a value
  // that is not finite may show it.
  std::string word;
  for (std::size_t i = 0; i <= s.size() && !contains(s, "not finite"); ++i) {
    const char c = i < s.size() ? s[i] : ' ';
    if (c == ' ' || c == ',' || c == ';' || c == ':' || c == '(' || c == ')' || c == '[' || c == ']' || c == '=' ||
        c == '%') {
      if (word == "inf" || word == "-inf" || word == "+inf" || word == "nan" || word == "-nan")
        out.push_back({"non-finite", "'" + word + "' printed as a value: say what it means"});
      word.clear();
    } else {
      word += c;
    }
  }
  if (contains(s, "infeasible") && contains(s, "eps-robust in continuous time") && !contains(s, "NOT eps-robust"))
    out.push_back({"contradiction", "infeasible and eps-robust in one line"});
  return out;
}

// Each line of `text` with the rules it breaks: "LINE\n  rule: why" per break; empty when clean.
inline std::string style_report(const std::string& text) {
  std::string out;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(pos, end - pos);
    const auto breaks = style_breaks(line);
    if (!breaks.empty()) {
      out += line + "\n";
      for (const auto& b : breaks) out += "  " + b.rule + ": " + b.why + "\n";
    }
    pos = end + 1;
  }
  return out;
}

}  // namespace marsyn::test
