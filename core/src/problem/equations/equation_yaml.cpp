#include "equation_yaml.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "equation_dynamics.hpp"
#include "marsyn/core/problem/config_error.hpp"

namespace marsyn::equations {

namespace {

using yaml::Field;

const std::vector<std::string> kKeys = {"states", "inputs", "constants", "params", "definitions", "field", "footprints", "periodic"};

bool has_model_keys(const Field& f) { return f.is_map() && (f.child("states").present() || f.child("field").present()); }

bool only_params(const Field& f) {
  if (!f.is_map()) return false;
  const auto keys = f.keys();
  return keys.size() == 1 && keys.front() == "params";
}

// A map's entries with their key and value fields, in document order.
struct Entry {
  std::string name;
  Field key, value;
};
std::vector<Entry> entries(const Field& map) {
  std::vector<Entry> out;
  if (!map.present()) return out;
  map.expect_map();
  for (const auto& kv : map.node()) {
    if (!kv.first.IsScalar()) Field(kv.first, map.file(), map.path(), map.node().Mark()).fail("expected a name as the key");
    const std::string name = kv.first.Scalar();
    const std::string path = map.path() + "." + name;
    out.push_back({name, Field(kv.first, map.file(), path, map.node().Mark()), Field(kv.second, map.file(), path, map.node().Mark())});
  }
  return out;
}

std::string expression_text(const Field& f) {
  if (!f.present() || !f.is_scalar()) f.fail("expected an expression (a string such as 'v * cos(theta)')");
  return f.node().Scalar();
}

double constant_value(const Field& f, const std::string& name) {
  if (!f.present() || !f.is_scalar()) f.fail("expected a number for the constant '" + name + "'");
  double v = 0;
  try {
    v = f.node().as<double>();
  } catch (const YAML::Exception&) {
    f.fail("expected a number for the constant '" + name + "', got '" + f.node().Scalar() + "'");
  }
  if (!std::isfinite(v)) f.fail("the constant '" + name + "' is not finite (got '" + f.node().Scalar() + "')");
  return v;
}

std::vector<std::string> read_file_lines(const std::string& file) {
  std::vector<std::string> lines;
  std::ifstream in(file);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

// The file position (0-based line, column) of character `offset` of the scalar `f` whose text is
// `text`: exact for plain and quoted scalars on one line and for block scalars (| and >); the
// scalar's start otherwise (e.g. escapes in a double-quoted string).
std::pair<int, int> file_position(const Field& f, const std::string& text, long offset) {
  const YAML::Mark m = f.node().Mark();
  if (m.line < 0) return {-1, -1};
  const auto lines = read_file_lines(f.file());
  if (m.line >= static_cast<int>(lines.size())) return {m.line, m.column};
  const std::string& l = lines[static_cast<std::size_t>(m.line)];
  const std::size_t col = static_cast<std::size_t>(m.column);
  const std::size_t off = static_cast<std::size_t>(offset);
  if (text.find('\n') == std::string::npos) {
    if (l.compare(col, text.size(), text) == 0) return {m.line, static_cast<int>(col + off)};
    if (col < l.size() && (l[col] == '"' || l[col] == '\'') && l.compare(col + 1, text.size(), text) == 0)
      return {m.line, static_cast<int>(col + 1 + off)};
  }
  if (col < l.size() && (l[col] == '|' || l[col] == '>')) {
    // Block scalar: the text's k-th line is the (k+1)-th file line after the indicator, indented.
    const std::string before = text.substr(0, std::min(off, text.size()));
    const int k = static_cast<int>(std::count(before.begin(), before.end(), '\n'));
    const std::size_t line_start = before.rfind('\n') == std::string::npos ? 0 : before.rfind('\n') + 1;
    const std::size_t line_end = text.find('\n', line_start);
    const std::string text_line = text.substr(line_start, line_end == std::string::npos ? std::string::npos : line_end - line_start);
    // The block's indentation is its first line's.
    const std::size_t first = static_cast<std::size_t>(m.line + 1), fl = first + static_cast<std::size_t>(k);
    if (fl < lines.size()) {
      const std::size_t indent = lines[first].find_first_not_of(' ');
      const std::string& L = lines[fl];
      if (indent != std::string::npos && L.compare(indent, text_line.size(), text_line) == 0)
        return {static_cast<int>(fl), static_cast<int>(indent + (off - line_start))};
    }
  }
  return {m.line, m.column};
}

[[noreturn]] void fail_in_expression(const Field& f, const std::string& text, long offset, const std::string& msg) {
  const auto [line, col] = file_position(f, text, offset);
  throw ConfigError(f.file(), line >= 0 ? line + 1 : 0, col >= 0 ? col + 1 : 0, f.path(), msg);
}

}  // namespace

bool is_equation_model(const Field& dynamics, const Field& default_dynamics) {
  return has_model_keys(dynamics) || (only_params(dynamics) && has_model_keys(default_dynamics));
}

std::shared_ptr<const Dynamics> load_equation_dynamics(const Field& agent_dynamics, const Field& default_dynamics) {
  // `{params: ...}` alone: the defaults' equations with this agent's constants.
  const bool inherited = only_params(agent_dynamics) && !has_model_keys(agent_dynamics);
  const Field model = inherited ? default_dynamics : agent_dynamics;
  model.expect_map();
  model.allow_only(kKeys);
  // The model's own `params`, then (when inherited) the agent's, which win.
  std::vector<Entry> overrides = entries(model.child("params"));
  if (inherited)
    for (auto& e : entries(agent_dynamics.child("params"))) overrides.push_back(e);

  EquationSpec spec;
  Field states = model.required("states"), inputs = model.required("inputs");
  std::vector<Field> state_f = states.items(), input_f = inputs.items();
  for (const auto& s : state_f) spec.states.push_back(s.text());
  for (const auto& s : input_f) spec.inputs.push_back(s.text());

  // Fields are never assigned to one another here: assigning a YAML::Node writes into the
  // document. Where a constant's value came from is kept as a pointer into these vectors.
  const std::vector<Entry> constants = entries(model.child("constants"));
  std::vector<const Field*> constant_at;
  for (const auto& c : constants) {
    spec.constants.emplace_back(c.name, constant_value(c.value, c.name));
    constant_at.push_back(&c.key);
  }
  // Per-agent values, like a plugin's parameters: only declared constants, finite numbers.
  for (const auto& p : overrides) {
    std::size_t i = 0;
    while (i < constants.size() && constants[i].name != p.name) ++i;
    if (i == constants.size()) {
      std::vector<std::string> names;
      for (const auto& c : constants) names.push_back(c.name);
      std::string msg = "unknown constant '" + p.name + "'";
      const std::string near = yaml::nearest(p.name, names);
      if (!near.empty()) msg += " (did you mean '" + near + "'?)";
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      p.key.fail(msg + "; the equations declare: " + (list.empty() ? "(no constants)" : list));
    }
    spec.constants[i].second = constant_value(p.value, p.name);
    constant_at[i] = &p.value;
  }

  const std::vector<Entry> definitions = entries(model.child("definitions"));
  for (const auto& d : definitions) spec.definitions.push_back({d.name, expression_text(d.value)});
  const Field field = model.required("field");
  field.expect_map();
  const std::vector<Entry> equations = entries(field);
  for (const auto& e : equations) spec.field.push_back({e.name, expression_text(e.value)});
  const std::vector<Entry> footprints = entries(model.child("footprints"));
  for (const auto& fp : footprints) {
    if (!fp.value.is_sequence() || fp.value.size() != 2)
      fp.value.fail("expected two expressions [x, y]: the footprint's point in the workspace plane");
    spec.footprints.push_back({fp.name, {expression_text(fp.value[0]), expression_text(fp.value[1])}});
  }

  const Field periodic = model.child("periodic");
  std::vector<Field> periodic_f = periodic.present() ? periodic.items() : std::vector<Field>{};
  for (const auto& p : periodic_f) spec.periodic.push_back(p.text());

  try {
    return std::make_shared<const EquationDynamics>(spec);
  } catch (const EquationError& e) {
    const std::string& s = e.section();
    const int i = e.index();
    const std::size_t si = static_cast<std::size_t>(i);
    if (s == "states") (i >= 0 ? state_f[si] : states).fail(e.what());
    if (s == "inputs") (i >= 0 ? input_f[si] : inputs).fail(e.what());
    if (s == "constants") constant_at[si]->fail(e.what());
    if (s == "periodic") (i >= 0 ? periodic_f[si] : periodic).fail(e.what());
    if (s == "field" && i < 0) field.fail(e.what());
    const Entry* entry = s == "definitions" ? &definitions[si]
                         : s == "field"     ? &equations[si]
                         : s == "footprints" ? &footprints[si]
                                             : nullptr;
    if (!entry) model.fail(e.what());
    if (e.offset() < 0) entry->key.fail(e.what());
    if (s == "definitions") fail_in_expression(entry->value, spec.definitions[si].text, e.offset(), e.what());
    if (s == "field") fail_in_expression(entry->value, spec.field[si].text, e.offset(), e.what());
    const std::size_t c = static_cast<std::size_t>(e.component());
    fail_in_expression(entry->value[c], spec.footprints[si].text[c], e.offset(), e.what());
  }
}

}  // namespace marsyn::equations
