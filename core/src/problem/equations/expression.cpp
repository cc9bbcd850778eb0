// The expression DAG (hash-consed nodes, constant folding) and the names an expression may use.
#include "expression.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <tuple>

#include "scalar_ops.hpp"

namespace marsyn::equations {

const std::vector<Function>& functions() {
  static const std::vector<Function> f = {{"sin", Op::Sin}, {"cos", Op::Cos},   {"tan", Op::Tan}, {"exp", Op::Exp},
                                          {"log", Op::Log}, {"sqrt", Op::Sqrt}, {"atan", Op::Atan}};
  return f;
}

std::string function_list() {
  std::string s;
  for (const auto& f : functions()) s += (s.empty() ? "" : ", ") + std::string(f.name);
  return s;
}

bool is_identifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

bool is_reserved(const std::string& s) {
  if (s == "pi") return true;
  for (const auto& f : functions())
    if (s == f.name) return true;
  return false;
}

// ---- the DAG ---------------------------------------------------------------------------------

int Graph::intern(const Node& n) {
  const auto key = std::make_tuple(static_cast<int>(n.op), n.a, n.b, n.k, std::bit_cast<std::uint64_t>(n.value));
  if (auto it = index_.find(key); it != index_.end()) return it->second;
  nodes_.push_back(n);
  const int id = static_cast<int>(nodes_.size()) - 1;
  index_.emplace(key, id);
  return id;
}

int Graph::constant(double v) {
  Node n;
  n.op = Op::Const;
  n.value = v;
  return intern(n);
}

int Graph::variable(int index) {
  Node n;
  n.op = Op::Var;
  n.k = index;
  n.deps = std::uint32_t{1} << index;
  return intern(n);
}

namespace {
double fold_unary(Op op, double x) {
  switch (op) {
    case Op::Neg: return -x;
    case Op::Sin: return ops::fn_sin(x);
    case Op::Cos: return ops::fn_cos(x);
    case Op::Tan: return ops::fn_tan(x);
    case Op::Exp: return ops::fn_exp(x);
    case Op::Log: return ops::fn_log(x);
    case Op::Sqrt: return ops::fn_sqrt(x);
    case Op::Atan: return ops::fn_atan(x);
    default: throw std::logic_error("not a unary operation");
  }
}
double fold_binary(Op op, double a, double b) {
  switch (op) {
    case Op::Add: return a + b;
    case Op::Sub: return a - b;
    case Op::Mul: return a * b;
    case Op::Div: return a / b;
    default: throw std::logic_error("not a binary operation");
  }
}
double checked(double v) {
  if (!std::isfinite(v)) throw std::domain_error("this constant sub-expression is not finite (" + std::to_string(v) + ")");
  return v;
}
}  // namespace

int Graph::unary(Op op, int a) {
  if ((*this)[a].op == Op::Const) return constant(checked(fold_unary(op, (*this)[a].value)));
  Node n;
  n.op = op;
  n.a = a;
  n.deps = (*this)[a].deps;
  return intern(n);
}

int Graph::binary(Op op, int a, int b) {
  if ((*this)[a].op == Op::Const && (*this)[b].op == Op::Const)
    return constant(checked(fold_binary(op, (*this)[a].value, (*this)[b].value)));
  Node n;
  n.op = op;
  n.a = a;
  n.b = b;
  n.deps = (*this)[a].deps | (*this)[b].deps;
  return intern(n);
}

int Graph::power(int a, int k) {
  if (k == 0) return constant(1.0);  // x^0 = 1, as the integer power of any number
  if (k == 1) return a;
  if (k < 0) return binary(Op::Div, constant(1.0), power(a, -k));
  if ((*this)[a].op == Op::Const) return constant(checked(ops::fn_pow((*this)[a].value, k)));
  Node n;
  n.op = Op::Pow;
  n.a = a;
  n.k = k;
  n.deps = (*this)[a].deps;
  return intern(n);
}

}  // namespace marsyn::equations
