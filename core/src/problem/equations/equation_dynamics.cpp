#include "equation_dynamics.hpp"

#include <bit>
#include <cmath>
#include <cstdio>
#include <map>

#include "marsyn/dual.hpp"
#include "marsyn/number_text.hpp"

namespace marsyn::equations {

namespace {

std::string listing(const std::string& what, const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return what + ": " + (s.empty() ? "(none)" : s);
}

// The stable type name: a hash of everything that defines the model (FNV-1a, 64 bit).
std::string type_name(const EquationSpec& spec) {
  std::uint64_t h = 1469598103934665603ull;
  auto add = [&](const std::string& s) {
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
    h = (h ^ 0xffu) * 1099511628211ull;
  };
  for (const auto& s : spec.states) add("s:" + s);
  for (const auto& s : spec.inputs) add("u:" + s);
  for (const auto& [name, v] : spec.constants) add("c:" + name + "=" + hex_double(v));
  for (const auto& d : spec.definitions) add("d:" + d.name + "=" + d.text);
  for (const auto& f : spec.field) add("f:" + f.name + "=" + f.text);
  for (const auto& f : spec.footprints) add("p:" + f.name + "=" + f.text[0] + "," + f.text[1]);
  char buf[32];
  std::snprintf(buf, sizeof buf, "equations:%08llx", static_cast<unsigned long long>(h >> 32 ^ (h & 0xffffffffull)));
  return buf;
}

}  // namespace

namespace {

// Node `id` changes by a whole multiple of 2 pi when variable v does: v itself, k v (k a whole
// number), and sums, differences and negations of such terms and terms without v.
bool whole_turns_of(const Graph& g, int id, int v) {
  const Node& e = g[id];
  if (((e.deps >> v) & 1u) == 0) return true;
  switch (e.op) {
    case Op::Var:
      return e.k == v;
    case Op::Neg:
      return whole_turns_of(g, e.a, v);
    case Op::Add:
    case Op::Sub:
      return whole_turns_of(g, e.a, v) && whole_turns_of(g, e.b, v);
    case Op::Mul: {
      const Node &l = g[e.a], &r = g[e.b];
      auto whole = [](const Node& c) { return c.op == Op::Const && std::nearbyint(c.value) == c.value; };
      return (whole(l) && whole_turns_of(g, e.b, v)) || (whole(r) && whole_turns_of(g, e.a, v));
    }
    default:
      return false;
  }
}

// Node `id` is 2 pi-periodic in variable v: v appears only as the argument of sin, cos or tan
// shifted by whole turns (a sufficient condition, read off the expression).
bool periodic_in(const Graph& g, int id, int v) {
  const Node& e = g[id];
  if (((e.deps >> v) & 1u) == 0) return true;
  switch (e.op) {
    case Op::Sin:
    case Op::Cos:
    case Op::Tan:
      return whole_turns_of(g, e.a, v);
    case Op::Var:
      return false;
    default:
      return (e.a < 0 || periodic_in(g, e.a, v)) && (e.b < 0 || periodic_in(g, e.b, v));
  }
}

}  // namespace

EquationDynamics::EquationDynamics(const EquationSpec& spec) : spec_(spec), type_(type_name(spec)) {
  const int n = static_cast<int>(spec.states.size()), m = static_cast<int>(spec.inputs.size());
  if (n == 0) throw EquationError("states", -1, "expected at least one state");
  if (m == 0) throw EquationError("inputs", -1, "expected at least one input");
  if (n + m > kMaxDual)
    throw EquationError("states", -1,
                        "at most " + std::to_string(kMaxDual) + " states and inputs together (marsyn::kMaxDual), got " +
                            std::to_string(n + m));

  // Every name once: states, inputs, constants, definitions; none a function or `pi`.
  Graph g;
  std::map<std::string, int> symbols;
  std::map<std::string, std::string> kind_of;
  auto declare = [&](const std::string& section, int index, const std::string& name, const std::string& kind, int node) {
    if (!is_identifier(name))
      throw EquationError(section, index, "'" + name + "' is not a name (letters, digits and '_', not starting with a digit)");
    if (is_reserved(name))
      throw EquationError(section, index, "'" + name + "' is reserved (a function or pi); choose another name");
    if (auto it = kind_of.find(name); it != kind_of.end())
      throw EquationError(section, index, "the name '" + name + "' is used twice (also " + it->second + ")");
    kind_of[name] = kind;
    symbols[name] = node;
  };
  for (int i = 0; i < n; ++i) declare("states", i, spec.states[i], "a state", g.variable(i));
  for (int j = 0; j < m; ++j) declare("inputs", j, spec.inputs[j], "an input", g.variable(n + j));
  for (std::size_t c = 0; c < spec.constants.size(); ++c) {
    const auto& [name, v] = spec.constants[c];
    if (!std::isfinite(v)) throw EquationError("constants", static_cast<int>(c), "the constant '" + name + "' is not finite");
    declare("constants", static_cast<int>(c), name, "a constant", g.constant(v));
  }
  std::vector<std::string> constant_names;
  for (const auto& [name, v] : spec.constants) constant_names.push_back(name);
  auto known = [&] {
    std::vector<std::string> defs;
    for (const auto& d : spec.definitions)
      if (symbols.count(d.name)) defs.push_back(d.name);
    std::string k = listing("states", spec.states) + "; " + listing("inputs", spec.inputs) + "; " +
                    listing("constants", constant_names);
    if (!defs.empty()) k += "; " + listing("definitions", defs);
    return k + "; and pi";
  };
  auto parse_at = [&](const std::string& section, int index, int component, const std::string& text) {
    try {
      return parse(text, g, symbols, known());
    } catch (const ExprError& e) {
      throw EquationError(section, index, e.what(), component, static_cast<long>(e.offset()));
    }
  };
  for (std::size_t d = 0; d < spec.definitions.size(); ++d) {
    const int node = parse_at("definitions", static_cast<int>(d), 0, spec.definitions[d].text);
    declare("definitions", static_cast<int>(d), spec.definitions[d].name, "a definition", node);
  }

  // One equation per state.
  std::vector<int> roots(static_cast<std::size_t>(n), -1);
  for (std::size_t e = 0; e < spec.field.size(); ++e) {
    const auto& f = spec.field[e];
    int i = -1;
    for (int s = 0; s < n; ++s)
      if (spec.states[s] == f.name) i = s;
    if (i < 0)
      throw EquationError("field", static_cast<int>(e),
                          "'" + f.name + "' is not a state; the field gives one equation per state (" +
                              listing("states", spec.states) + ")");
    if (roots[i] >= 0) throw EquationError("field", static_cast<int>(e), "a second equation for the state '" + f.name + "'");
    roots[i] = parse_at("field", static_cast<int>(e), 0, f.text);
  }
  for (int i = 0; i < n; ++i)
    if (roots[i] < 0) throw EquationError("field", -1, "the state '" + spec.states[i] + "' has no equation");
  field_ = Program(g, roots, n, m);
  std::uint32_t read = 0;
  for (int r : roots) read |= g[r].deps;
  independent_.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) independent_[i] = ((read >> i) & 1u) == 0;

  // Footprints: two coordinates each, of the state only.
  std::vector<std::pair<int, int>> footprint_roots;  // (footprint, node)
  std::map<std::string, int> seen;
  for (std::size_t p = 0; p < spec.footprints.size(); ++p) {
    const auto& fp = spec.footprints[p];
    if (!is_identifier(fp.name))
      throw EquationError("footprints", static_cast<int>(p), "'" + fp.name + "' is not a name");
    if (seen.count(fp.name)) throw EquationError("footprints", static_cast<int>(p), "the footprint '" + fp.name + "' is given twice");
    seen[fp.name] = 1;
    std::vector<int> pr;
    for (int c = 0; c < 2; ++c) {
      const int node = parse_at("footprints", static_cast<int>(p), c, fp.text[c]);
      const std::uint32_t inputs_read = g[node].deps >> n;
      if (inputs_read != 0)
        throw EquationError("footprints", static_cast<int>(p),
                            "a footprint is a function of the state only; this coordinate reads the input '" +
                                spec.inputs[static_cast<std::size_t>(std::countr_zero(inputs_read))] + "'",
                            c, 0);
      pr.push_back(node);
      footprint_roots.emplace_back(static_cast<int>(p), node);
    }
    footprint_programs_.emplace_back(g, pr, n, 0);
  }

  periodic_.assign(static_cast<std::size_t>(n), false);
  for (std::size_t q = 0; q < spec.periodic.size(); ++q) {
    const std::string& name = spec.periodic[q];
    int v = -1;
    for (int s = 0; s < n; ++s)
      if (spec.states[s] == name) v = s;
    if (v < 0)
      throw EquationError("periodic", static_cast<int>(q), "'" + name + "' is not a state (" + listing("states", spec.states) + ")");
    const std::string why = " is not 2 pi-periodic in '" + name + "': '" + name +
                            "' may appear only inside sin, cos or tan of a whole multiple of it plus terms without it";
    for (int i = 0; i < n; ++i)
      if (!periodic_in(g, roots[i], v))
        throw EquationError("periodic", static_cast<int>(q), "the equation of '" + spec.states[i] + "'" + why);
    for (const auto& [p, node] : footprint_roots)
      if (!periodic_in(g, node, v))
        throw EquationError("periodic", static_cast<int>(q), "the footprint '" + spec.footprints[static_cast<std::size_t>(p)].name + "'" + why);
    periodic_[v] = true;
  }
}

std::vector<std::string> EquationDynamics::footprints() const {
  std::vector<std::string> names;
  for (const auto& f : spec_.footprints) names.push_back(f.name);
  return names;
}

}  // namespace marsyn::equations
