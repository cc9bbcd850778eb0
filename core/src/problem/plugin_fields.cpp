#include "plugin_fields.hpp"

#include <climits>
#include <cmath>

#include "field_text.hpp"

namespace marsyn::loader {

std::string unknown_plugin(const PluginRegistry& reg, const std::string& kind, const std::string& name) {
  std::string msg = "unknown " + kind + " plugin '" + name + "'";
  const std::string near = yaml::nearest(name, reg.names(kind));
  if (!near.empty()) msg += " (did you mean '" + near + "'?)";
  msg += "; available: " + join(reg.names(kind));
  for (const auto& p : reg.problems())
    if (p.reason.find("API version") != std::string::npos) msg += "; skipped " + p.library_path + ": " + p.reason;
  return msg;
}

// A declared range such as "[1, inf)", "[0, 12]" or "-1 or [0, inf)"; false when the text is
// not of that form (the range is then documentation only).
bool in_declared_range(const std::string& range, long v, bool* understood) {
  *understood = false;
  auto trim = [](std::string t) {
    while (!t.empty() && t.front() == ' ') t.erase(0, 1);
    while (!t.empty() && t.back() == ' ') t.pop_back();
    return t;
  };
  auto number = [&](const std::string& t, double* out) {
    const std::string u = trim(t);
    if (u == "inf" || u == "+inf") return *out = INFINITY, true;
    if (u == "-inf") return *out = -INFINITY, true;
    if (u.empty()) return false;
    char* end = nullptr;
    *out = std::strtod(u.c_str(), &end);
    return end && *end == '\0';
  };
  std::vector<std::string> parts;
  std::string rest = range;
  for (std::size_t at; (at = rest.find(" or ")) != std::string::npos; rest = rest.substr(at + 4))
    parts.push_back(rest.substr(0, at));
  parts.push_back(rest);
  bool inside = false;
  for (const auto& raw : parts) {
    const std::string p = trim(raw);
    double a = 0, b = 0;
    if (number(p, &a)) {
      inside = inside || static_cast<double>(v) == a;
      continue;
    }
    const auto comma = p.find(',');
    if (p.size() < 5 || comma == std::string::npos || (p.front() != '[' && p.front() != '(') ||
        (p.back() != ']' && p.back() != ')') || !number(p.substr(1, comma - 1), &a) ||
        !number(p.substr(comma + 1, p.size() - comma - 2), &b))
      return true;  // not understood: no check
    const double x = static_cast<double>(v);
    inside = inside || ((p.front() == '[' ? x >= a : x > a) && (p.back() == ']' ? x <= b : x < b));
  }
  *understood = true;
  return inside;
}

// Integer parameters are range-checked here, before a plugin narrows them (plugins store them as
// int): the 32-bit range first, then the range the plugin declares.
long checked_integer(const Field& v, const ParamSpec& spec, const PluginInfo& info) {
  const long x = v.integer_in(INT_MIN, INT_MAX, "integer plugin parameters are 32-bit");
  bool understood = false;
  if (!in_declared_range(spec.range, x, &understood) && understood)
    v.fail("expected an integer in " + spec.range + " (the range the " + info.kind + " '" + info.name +
           "' declares), got " + std::to_string(x));
  return x;
}

Params read_params(const Field& f, const PluginInfo& info) {
  Params params;
  if (!f.present()) return params;
  f.expect_map();
  std::vector<std::string> allowed;
  for (const auto& s : info.params) allowed.push_back(s.name);
  if (allowed.empty() && !f.keys().empty())
    f.child(f.keys().front()).fail("the " + info.kind + " '" + info.name + "' takes no parameters");
  f.allow_only(allowed);
  for (const auto& spec : info.params) {
    Field v = f.child(spec.name);
    if (!v.present()) continue;
    switch (spec.type) {
      case ParamType::Bool: params.set(spec.name, v.boolean()); break;
      case ParamType::Int: params.set(spec.name, checked_integer(v, spec, info)); break;
      case ParamType::Real: params.set(spec.name, v.real()); break;
      case ParamType::String: params.set(spec.name, v.text()); break;
      case ParamType::RealVector: {
        const Eigen::VectorXd x = v.vector(-1, "");
        params.set(spec.name, std::vector<double>(x.data(), x.data() + x.size()));
        break;
      }
    }
  }
  return params;
}

PluginField read_plugin_field(const Field& f, const std::string& name_key, const std::string& extra_key) {
  if (f.is_scalar()) return {f.text(), f, f.child("params")};
  f.expect_map();
  if (extra_key.empty()) f.allow_only({name_key, "params"});
  else f.allow_only({name_key, "params", extra_key});
  Field n = f.required(name_key);
  return {n.text(), n, f.child("params")};
}

}  // namespace marsyn::loader
