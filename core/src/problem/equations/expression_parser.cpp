// The expression parser: text to nodes of a Graph (expression.hpp), with located errors.
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>

#include "../yaml_reader.hpp"  // yaml::nearest, for suggestions
#include "expression.hpp"
#include "scalar_ops.hpp"

namespace marsyn::equations {

// ---- the parser ------------------------------------------------------------------------------
//   expr    := term (('+' | '-') term)*
//   term    := unary (('*' | '/') unary)*
//   unary   := ('-' | '+') unary | power
//   power   := primary ('^' unary)?          (right-associative; -x^2 = -(x^2))
//   primary := number | name | function '(' expr ')' | '(' expr ')'
namespace {

class Parser {
 public:
  Parser(const std::string& text, Graph& g, const std::map<std::string, int>& symbols, const std::string& known)
      : s_(text), g_(g), symbols_(symbols), known_(known) {}

  int run() {
    skip();
    if (pos_ >= s_.size()) fail(pos_, "the expression is empty");
    const int r = expr();
    skip();
    if (pos_ < s_.size()) fail(pos_, "unexpected '" + std::string(1, s_[pos_]) + "' (expected an operator or the end)");
    return r;
  }

 private:
  [[noreturn]] void fail(std::size_t at, const std::string& msg) const {
    throw ExprError(at, "syntax error at column " + std::to_string(at + 1) + " of the expression: " + msg);
  }
  [[noreturn]] void fail_plain(std::size_t at, const std::string& msg) const { throw ExprError(at, msg); }

  void skip() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  bool accept(char c) {
    skip();
    if (pos_ < s_.size() && s_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }

  // Folding errors (a constant sub-expression that is not finite) are located at its start.
  template <class F>
  int folded(std::size_t at, F&& make) {
    try {
      return make();
    } catch (const std::domain_error& e) {
      fail_plain(at, e.what());
    }
  }

  // Every nesting (parentheses, function arguments) passes through expr(), every sign and
  // exponent through unary() and power(); the depth limit keeps a pathological expression from overflowing the stack.
  struct Depth {
    Parser& p;
    explicit Depth(Parser& parser, std::size_t at) : p(parser) {
      if (++p.depth_ > kMaxDepth) p.fail_plain(at, "the expression is nested more than " + std::to_string(kMaxDepth) + " levels deep");
    }
    ~Depth() { --p.depth_; }
  };
  static constexpr int kMaxDepth = 200;

  int expr() {
    skip();
    const std::size_t start = pos_;
    const Depth guard(*this, start);
    int left = term();
    for (;;) {
      if (accept('+')) {
        const int r = term();
        left = folded(start, [&] { return g_.binary(Op::Add, left, r); });
      } else if (accept('-')) {
        const int r = term();
        left = folded(start, [&] { return g_.binary(Op::Sub, left, r); });
      } else {
        return left;
      }
    }
  }

  int term() {
    skip();
    const std::size_t start = pos_;
    int left = unary();
    for (;;) {
      if (accept('*')) {
        const int r = unary();
        left = folded(start, [&] { return g_.binary(Op::Mul, left, r); });
      } else if (accept('/')) {
        const int r = unary();
        left = folded(start, [&] { return g_.binary(Op::Div, left, r); });
      } else {
        return left;
      }
    }
  }

  int unary() {
    skip();
    const std::size_t start = pos_;
    if (accept('-')) {
      const Depth guard(*this, start);
      const int a = unary();
      return folded(start, [&] { return g_.unary(Op::Neg, a); });
    }
    if (accept('+')) {
      const Depth guard(*this, start);
      return unary();
    }
    return power();
  }

  int power() {
    skip();
    const std::size_t start = pos_;
    const int base = primary();
    if (!accept('^')) return base;
    skip();
    const std::size_t at = pos_;
    const Depth guard(*this, at);
    const int e = unary();
    const Node& en = g_[e];
    if (en.op != Op::Const)
      fail_plain(at, "the exponent after '^' must be an integer constant (it reads a state or an input)");
    if (en.value != std::floor(en.value) || std::fabs(en.value) > 64)
      fail_plain(at, "the exponent after '^' must be an integer in [-64, 64], got " + std::to_string(en.value) +
                         " (write exp(e * log(x)) for other powers of positive x)");
    const int k = static_cast<int>(en.value);
    return folded(start, [&] { return g_.power(base, k); });
  }

  int primary() {
    skip();
    if (pos_ >= s_.size()) fail(pos_, "unexpected end of the expression (expected a number, a name or '(')");
    const char c = s_[pos_];
    const std::size_t start = pos_;
    if (c == '(') {
      ++pos_;
      const int r = expr();
      if (!accept(')')) fail(pos_, pos_ < s_.size() ? "expected ')' before '" + std::string(1, s_[pos_]) + "'"
                                                    : "expected ')' (the '(' at column " + std::to_string(start + 1) +
                                                          " is not closed)");
      return r;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return number();
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_')) ++pos_;
      const std::string name = s_.substr(start, pos_ - start);
      skip();
      if (pos_ < s_.size() && s_[pos_] == '(') {
        const Function* fn = nullptr;
        for (const auto& f : functions())
          if (name == f.name) fn = &f;
        if (!fn)
          fail_plain(start, "unsupported function '" + name + "' (supported: " + function_list() +
                                (symbols_.count(name) ? "; '" + name + "' is a symbol, not a function" : "") + ")");
        ++pos_;
        const int arg = expr();
        if (accept(',')) fail(pos_ - 1, "'" + name + "' takes one argument");
        if (!accept(')')) fail(pos_, "expected ')' closing " + name + "(");
        return folded(start, [&] { return g_.unary(fn->op, arg); });
      }
      if (auto it = symbols_.find(name); it != symbols_.end()) return it->second;
      if (name == "pi") return g_.constant(std::numbers::pi);
      for (const auto& f : functions())
        if (name == f.name) fail_plain(start, "'" + name + "' is a function: write " + name + "(...)");
      std::vector<std::string> names{"pi"};
      for (const auto& [n, id] : symbols_) names.push_back(n);
      const std::string near = yaml::nearest(name, names);
      fail_plain(start, "unknown symbol '" + name + "'" + (near.empty() ? "" : " (did you mean '" + near + "'?)") + "; " + known_);
    }
    fail(pos_, "unexpected '" + std::string(1, c) + "' (expected a number, a name or '(')");
  }

  int number() {
    const std::size_t start = pos_;
    while (pos_ < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '.')) ++pos_;
    if (pos_ < s_.size() && (s_[pos_] == 'e' || s_[pos_] == 'E')) {
      std::size_t p = pos_ + 1;
      if (p < s_.size() && (s_[p] == '+' || s_[p] == '-')) ++p;
      if (p < s_.size() && std::isdigit(static_cast<unsigned char>(s_[p]))) {
        pos_ = p;
        while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_;
      }
    }
    double v = 0;
    const auto r = std::from_chars(s_.data() + start, s_.data() + pos_, v);
    if (r.ec == std::errc::result_out_of_range)
      fail_plain(start, "the number '" + s_.substr(start, pos_ - start) + "' is outside the range of finite doubles");
    if (r.ec != std::errc() || r.ptr != s_.data() + pos_)
      fail(start, "malformed number '" + s_.substr(start, pos_ - start) + "'");
    if (!std::isfinite(v)) fail_plain(start, "the number '" + s_.substr(start, pos_ - start) + "' is not finite");
    if (pos_ < s_.size() && (std::isalpha(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_'))
      fail(pos_, "a name right after the number '" + s_.substr(start, pos_ - start) + "' (write '*' for a product)");
    return g_.constant(v);
  }

  const std::string& s_;
  Graph& g_;
  const std::map<std::string, int>& symbols_;
  const std::string& known_;
  std::size_t pos_ = 0;
  int depth_ = 0;
};

}  // namespace

int parse(const std::string& text, Graph& g, const std::map<std::string, int>& symbols, const std::string& known) {
  return Parser(text, g, symbols, known).run();
}

}  // namespace marsyn::equations
