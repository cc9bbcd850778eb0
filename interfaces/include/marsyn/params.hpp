#pragma once
// Typed plugin parameters, declared once by each plugin (in the spirit of OMPL's ParamSet) so
// that the config loader can reject unknown names and wrong types with the exact YAML location,
// and so that `marsyn plugins --params` and parameter searches can enumerate them.
// marsyn/param_set.hpp builds both the ParamSpecs and the parsing from one declaration per
// parameter, bound to a member of the plugin's options struct (the planners use it).
#include <map>
#include <string>
#include <variant>
#include <vector>

#include "marsyn/error.hpp"

namespace marsyn {

enum class ParamType { Bool, Int, Real, String, RealVector };

inline const char* to_string(ParamType t) {
  switch (t) {
    case ParamType::Bool: return "a boolean";
    case ParamType::Int: return "an integer";
    case ParamType::Real: return "a number";
    case ParamType::String: return "a string";
    case ParamType::RealVector: return "a list of numbers";
  }
  return "?";
}

struct ParamSpec {
  std::string name;
  ParamType type = ParamType::Real;
  std::string default_value;  // as text, for help output
  std::string range;          // e.g. "(0, inf)" or "sst|rrt|kpiece1", for help and searches
  std::string doc;
};

using ParamValue = std::variant<bool, long, double, std::string, std::vector<double>>;

// Values set in the config, already checked against the plugin's ParamSpecs for type.
class Params {
 public:
  void set(const std::string& name, ParamValue v) { values_[name] = std::move(v); }
  bool has(const std::string& name) const { return values_.count(name) != 0; }
  const std::map<std::string, ParamValue>& values() const { return values_; }

  double real(const std::string& name, double fallback) const {
    auto it = values_.find(name);
    if (it == values_.end()) return fallback;
    if (auto* d = std::get_if<double>(&it->second)) return *d;
    if (auto* l = std::get_if<long>(&it->second)) return static_cast<double>(*l);
    throw ParamError(name, "expected a number");
  }
  long integer(const std::string& name, long fallback) const {
    auto it = values_.find(name);
    if (it == values_.end()) return fallback;
    if (auto* l = std::get_if<long>(&it->second)) return *l;
    throw ParamError(name, "expected an integer");
  }
  bool boolean(const std::string& name, bool fallback) const {
    auto it = values_.find(name);
    if (it == values_.end()) return fallback;
    if (auto* b = std::get_if<bool>(&it->second)) return *b;
    throw ParamError(name, "expected true or false");
  }
  std::string text(const std::string& name, const std::string& fallback) const {
    auto it = values_.find(name);
    if (it == values_.end()) return fallback;
    if (auto* s = std::get_if<std::string>(&it->second)) return *s;
    throw ParamError(name, "expected a string");
  }
  std::vector<double> reals(const std::string& name, std::vector<double> fallback) const {
    auto it = values_.find(name);
    if (it == values_.end()) return fallback;
    if (auto* v = std::get_if<std::vector<double>>(&it->second)) return *v;
    throw ParamError(name, "expected a list of numbers");
  }

 private:
  std::map<std::string, ParamValue> values_;
};

}  // namespace marsyn
