#pragma once
// ParamSet<Options>: each plugin parameter declared once, bound to a member of the plugin's
// options struct (in the spirit of OMPL's ParamSet::declareParam). That one declaration gives
//   - the default: the member's initializer in the struct, nowhere else;
//   - the listing: ParamSpec{name, type, default as text, range, doc}, in declaration order;
//   - the parsing: Params -> Options, members read in declaration order;
//   - the checks: a Rule on the value (require) or any check on the options (check), run right
//     after the value is read, or after every value is read (require_last, check_last: for
//     cross-parameter rules, or a rule reported after the other parameters' rules);
//   - listed_as: the default's text in the listing where the member's value does not say it.
// The type comes from the member (bool, int, long, double, std::string, std::vector<double>).
// A member of a member (`&Options::successor, &SuccessorOptions::substeps`) binds a parameter
// kept in a nested struct, so that the struct the plugin's code reads is the one declared.
// Integer ranges are also enforced by the loader from the declared range text (problem_loader).
//
//   struct Options { double r_input = 0.01; std::string mode = "fast"; int steps = 10; ... };
//   ParamSet<Options> declare() {
//     ParamSet<Options> s;
//     s.add("r_input", &Options::r_input, "[0, inf)", "input weight")
//         .require({[](double v) { return v >= 0; }, "expected a number >= 0"});
//     s.choice("mode", &Options::mode, {"fast", "exact"}, "how to solve");  // "expected fast or exact"
//     s.add("steps", &Options::steps, "[1, inf)", "steps per period");
//     return s;
//   }
//   static std::vector<ParamSpec> param_specs() { return declared_once<declare>().specs(); }
//   explicit MyPlugin(const Params& p) : options_(declared_once<declare>().parse(p)) {}
//
// Additive to params.hpp: plugins that build their ParamSpecs by hand keep working.
#include <charconv>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "marsyn/error.hpp"
#include "marsyn/number_text.hpp"
#include "marsyn/params.hpp"

namespace marsyn {

// How a number's default is written in the listing. Both exist so that existing listings stay
// byte-identical: Shortest is the shortest text that reads back to the same double, exponent
// without '+' or leading zeros ("1e-6", "2e7", "0.01"); Stream is six significant digits as
// `std::ostream << v` prints them ("1e-06", "1e+08").
enum class NumberText { Shortest, Stream };

namespace detail {

inline std::string number_text(double v, NumberText style) {
  char buf[64];
  if (style == NumberText::Stream) {  // exactly as `std::ostream << v` prints it
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
  }
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, r.ptr);
  const auto e = s.find('e');
  if (e == std::string::npos) return s;
  std::string exp = s.substr(e + 1);
  std::string sign;
  if (!exp.empty() && (exp[0] == '+' || exp[0] == '-')) {
    if (exp[0] == '-') sign = "-";
    exp.erase(0, 1);
  }
  while (exp.size() > 1 && exp[0] == '0') exp.erase(0, 1);
  return s.substr(0, e + 1) + sign + exp;
}

template <class T>
constexpr ParamType param_type_of() {
  if constexpr (std::is_same_v<T, bool>) return ParamType::Bool;
  else if constexpr (std::is_same_v<T, int> || std::is_same_v<T, long>) return ParamType::Int;
  else if constexpr (std::is_same_v<T, double>) return ParamType::Real;
  else if constexpr (std::is_same_v<T, std::string>) return ParamType::String;
  else {
    static_assert(std::is_same_v<T, std::vector<double>>, "parameter members are bool, int, long, double, string or vector<double>");
    return ParamType::RealVector;
  }
}

}  // namespace detail

// A condition on one parameter's value and the message that refuses a value failing it.
template <class T>
struct Rule {
  std::function<bool(const T&)> ok;
  std::string message;
};

// When a rule runs: as soon as its value is read, or after every value is read (require, require_last).
enum class Checked { on_read, last };

template <class Options>
class ParamSet {
 public:
  // Throws ParamError(field, message) when the options are not acceptable.
  using Check = std::function<void(const Options&)>;

 private:
  struct Declaration {
    ParamSpec spec;  // default_value is filled in by specs()
    std::function<void(const Params&, Options&)> read;
    std::function<std::string(const Options&, NumberText)> text;
    std::vector<Check> now, last;
    std::optional<std::string> listed;  // listed_as(): the default's text in the listing
  };

 public:
  // What add() returns: attaches checks to the declaration just made.
  template <class T>
  class Declared {
   public:
    using value_type = T;
    using Get = std::function<const T&(const Options&)>;
    Declared(Declaration& d, Get get) : d_(d), get_(std::move(get)) {}
    // Refused with ParamError(name, rule.message) right after the value is read.
    Declared& require(Rule<T> rule) {
      d_.now.push_back(refuse_unless(std::move(rule)));
      return *this;
    }
    // ... after every parameter is read (a rule reported after the other parameters' rules).
    Declared& require_last(Rule<T> rule) {
      d_.last.push_back(refuse_unless(std::move(rule)));
      return *this;
    }
    // ... refused with ParamError(reported_as, rule.message): one message that speaks for
    // several parameters, reported under one name ("weights must be non-negative" under r_input).
    Declared& require_last(Rule<T> rule, std::string reported_as) {
      d_.last.push_back(refuse_unless(std::move(rule), std::move(reported_as)));
      return *this;
    }
    // Any check on the options: right after this value is read (earlier parameters are read,
    // later ones hold their defaults), or after every value is read (cross-parameter rules).
    Declared& check(Check c) {
      d_.now.push_back(std::move(c));
      return *this;
    }
    Declared& check_last(Check c) {
      d_.last.push_back(std::move(c));
      return *this;
    }
    // The default as the listing writes it, where the member's initial value does not say what
    // it means (an empty list standing for "0.1 eps"). The parsing still starts from the member.
    Declared& listed_as(std::string text) {
      d_.listed = std::move(text);
      return *this;
    }

   private:
    Check refuse_unless(Rule<T> rule) const { return refuse_unless(std::move(rule), d_.spec.name); }
    Check refuse_unless(Rule<T> rule, std::string field) const {
      return [field = std::move(field), get = get_, rule = std::move(rule)](const Options& o) {
        if (!rule.ok(get(o))) throw ParamError(field, rule.message);
      };
    }
    Declaration& d_;
    Get get_;
  };

  explicit ParamSet(NumberText numbers = NumberText::Shortest) : numbers_(numbers) {}

  template <class T>
  Declared<T> add(std::string name, T Options::*member, std::string range, std::string doc) {
    return bind<T>(std::move(name), [member](auto& o) -> auto& { return o.*member; }, std::move(range), std::move(doc));
  }
  template <class Part, class T>
  Declared<T> add(std::string name, Part Options::*part, T Part::*member, std::string range, std::string doc) {
    return bind<T>(std::move(name), [part, member](auto& o) -> auto& { return (o.*part).*member; }, std::move(range),
                   std::move(doc));
  }

  // A string parameter with a closed set of values: range "a|b|c"; any other value is refused
  // with "expected a, b or c" right after it is read.
  Declared<std::string> choice(std::string name, std::string Options::*member, std::vector<std::string> values,
                               std::string doc) {
    std::string range, expected;
    for (std::size_t i = 0; i < values.size(); ++i) {
      range += (i ? "|" : "") + values[i];
      expected += (i == 0 ? "" : i + 1 == values.size() ? " or " : ", ") + values[i];
    }
    auto d = add(std::move(name), member, std::move(range), std::move(doc));
    d.require({[values](const std::string& v) {
                 for (const auto& allowed : values)
                   if (v == allowed) return true;
                 return false;
               },
               "expected " + expected});
    return d;
  }

  // An integer parameter in [lo, hi] (an int or long member, or a member of a member: `path`):
  // the listed range "[lo, hi]" and the message "expected an integer in [lo, hi]" come from the
  // one pair; a long member is checked before anything narrows it.
  template <class... Path>
  auto integer(std::string name, long lo, long hi, std::string doc, Checked when, Path... path) {
    const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    auto d = add(std::move(name), path..., range, std::move(doc));
    using T = typename decltype(d)::value_type;
    static_assert(std::is_same_v<T, int> || std::is_same_v<T, long>, "integer() binds an int or long member");
    Rule<T> within{[lo, hi](const T& v) { return v >= lo && v <= hi; }, "expected an integer in " + range};
    if (when == Checked::last)
      d.require_last(std::move(within));
    else
      d.require(std::move(within));
    return d;
  }

  // The listing: one ParamSpec per declaration, defaults from a default-constructed Options.
  std::vector<ParamSpec> specs() const {
    const Options defaults{};
    std::vector<ParamSpec> out;
    for (const auto& d : decls_) {
      ParamSpec s = d.spec;
      s.default_value = d.listed ? *d.listed : d.text(defaults, numbers_);
      out.push_back(std::move(s));
    }
    return out;
  }

  // The parsing: defaults, then each declared parameter read and checked in declaration order,
  // then the check_last rules in declaration order. Throws ParamError.
  Options parse(const Params& p) const {
    Options o{};
    for (const auto& d : decls_) {
      d.read(p, o);
      for (const auto& c : d.now) c(o);
    }
    for (const auto& d : decls_)
      for (const auto& c : d.last) c(o);
    return o;
  }

 private:
  // `at(options)` is the member, const or not.
  template <class T, class At>
  Declared<T> bind(std::string name, At at, std::string range, std::string doc) {
    Declaration& d = decls_.emplace_back();
    d.spec = {name, detail::param_type_of<T>(), "", std::move(range), std::move(doc)};
    d.read = [name, at](const Params& p, Options& o) { at(o) = read_value(p, name, at(o)); };
    d.text = [at](const Options& o, NumberText style) { return value_text(at(o), style); };
    return Declared<T>(d, [at](const Options& o) -> const T& { return at(o); });
  }

  static bool read_value(const Params& p, const std::string& n, bool v) { return p.boolean(n, v); }
  static int read_value(const Params& p, const std::string& n, int v) { return static_cast<int>(p.integer(n, v)); }
  static long read_value(const Params& p, const std::string& n, long v) { return p.integer(n, v); }
  static double read_value(const Params& p, const std::string& n, double v) { return p.real(n, v); }
  static std::string read_value(const Params& p, const std::string& n, const std::string& v) { return p.text(n, v); }
  static std::vector<double> read_value(const Params& p, const std::string& n, const std::vector<double>& v) {
    return p.reals(n, v);
  }

  static std::string value_text(bool v, NumberText) { return v ? "true" : "false"; }
  static std::string value_text(int v, NumberText) { return std::to_string(v); }
  static std::string value_text(long v, NumberText) { return std::to_string(v); }
  static std::string value_text(double v, NumberText style) { return detail::number_text(v, style); }
  static std::string value_text(const std::string& v, NumberText) { return v; }
  static std::string value_text(const std::vector<double>& v, NumberText style) {
    std::string s = "[";
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + detail::number_text(v[i], style);
    return s + "]";
  }

  NumberText numbers_;
  std::deque<Declaration> decls_;  // a deque: add() hands out references that later adds keep valid
};

// The ParamSet that `Declare` (a function returning a ParamSet) builds, built on first use and
// kept for the program's life: the one set that a plugin's listing and parsing both read.
//   std::vector<ParamSpec> Options::specs() { return declared_once<declare>().specs(); }
//   Options Options::from(const Params& p) { return declared_once<declare>().parse(p); }
template <auto Declare>
const auto& declared_once() {
  static const auto set = Declare();
  return set;
}

}  // namespace marsyn
