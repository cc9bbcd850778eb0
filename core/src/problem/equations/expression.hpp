#pragma once
// Expressions of an equation model (docs/problem-format.md, "Dynamics as equations"): a small
// recursive-descent parser into a hash-consed DAG. Sub-expressions made only of numbers and
// constants are folded in double, exactly as a C++ plugin's compiler folds `mp_ * l_`; nothing
// else is rewritten, so the evaluation order is the one written.
#include <cstddef>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace marsyn::equations {

enum class Op : std::uint8_t { Const, Var, Neg, Add, Sub, Mul, Div, Pow, Sin, Cos, Tan, Exp, Log, Sqrt, Atan };

// The supported functions, in the order the messages list them.
struct Function {
  const char* name;
  Op op;
};
const std::vector<Function>& functions();
std::string function_list();  // "sin, cos, tan, exp, log, sqrt, atan"

struct Node {
  Op op = Op::Const;
  int a = -1, b = -1;   // operand node ids
  int k = 0;            // Var: variable index; Pow: the integer exponent
  double value = 0.0;   // Const
  std::uint32_t deps = 0;  // bit v set when the node reads variable v
};

// A parse or evaluation problem at `offset` (0-based, in characters) of the expression text.
class ExprError : public std::runtime_error {
 public:
  ExprError(std::size_t offset, const std::string& message) : std::runtime_error(message), offset_(offset) {}
  std::size_t offset() const { return offset_; }

 private:
  std::size_t offset_;
};

class Graph {
 public:
  int constant(double v);
  int variable(int index);
  // Folds when every operand is a constant; throws std::domain_error when a fold is not finite.
  int unary(Op op, int a);
  int binary(Op op, int a, int b);
  int power(int a, int k);

  const Node& operator[](int id) const { return nodes_[static_cast<std::size_t>(id)]; }
  int size() const { return static_cast<int>(nodes_.size()); }

 private:
  int intern(const Node& n);
  std::vector<Node> nodes_;
  std::map<std::tuple<int, int, int, int, std::uint64_t>, int> index_;
};

// Parses `text` into `g`; names resolve through `symbols` (name -> node id; `pi` is built in).
// `known` describes the available names for the unknown-symbol message.
int parse(const std::string& text, Graph& g, const std::map<std::string, int>& symbols, const std::string& known);

bool is_identifier(const std::string& s);
bool is_reserved(const std::string& s);  // a function name or `pi`

}  // namespace marsyn::equations
