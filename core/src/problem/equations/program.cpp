#include "program.hpp"

#include <set>
#include <stdexcept>

namespace marsyn::equations {

namespace {
bool leaf(const Node& n) { return n.op == Op::Const || n.op == Op::Var; }

Program::Code unary_code(Op op) {
  switch (op) {
    case Op::Neg: return Program::Code::Neg;
    case Op::Sin: return Program::Code::Sin;
    case Op::Cos: return Program::Code::Cos;
    case Op::Tan: return Program::Code::Tan;
    case Op::Exp: return Program::Code::Exp;
    case Op::Log: return Program::Code::Log;
    case Op::Sqrt: return Program::Code::Sqrt;
    case Op::Atan: return Program::Code::Atan;
    case Op::Pow: return Program::Code::Pow;
    default: throw std::logic_error("not a unary node");
  }
}

// Binary operations: slot-slot, slot-constant, constant-slot (both constant never: folded).
Program::Code binary_code(Op op, bool a_const, bool b_const) {
  using C = Program::Code;
  const int form = a_const ? 2 : b_const ? 1 : 0;
  switch (op) {
    case Op::Add: return form == 0 ? C::Add : form == 1 ? C::AddRC : C::AddCR;
    case Op::Sub: return form == 0 ? C::Sub : form == 1 ? C::SubRC : C::SubCR;
    case Op::Mul: return form == 0 ? C::Mul : form == 1 ? C::MulRC : C::MulCR;
    case Op::Div: return form == 0 ? C::Div : form == 1 ? C::DivRC : C::DivCR;
    default: throw std::logic_error("not a binary node");
  }
}
// The instruction computing node nd (its destination still to choose): a constant operand
// folds into the instruction, the others are read from their slots.
template <class SlotOf>
Program::Instr operation(const Graph& g, const Node& nd, const SlotOf& slot_of) {
  Program::Instr in{Program::Code::Copy, 0, -1, -1, 0, 0.0};
  if (nd.b >= 0) {
    const bool ac = g[nd.a].op == Op::Const, bc = g[nd.b].op == Op::Const;
    in.code = binary_code(nd.op, ac, bc);
    if (ac) {
      in.c = g[nd.a].value;
      in.a = slot_of(nd.b);
    } else {
      in.a = slot_of(nd.a);
      if (bc) in.c = g[nd.b].value;
      else in.b = slot_of(nd.b);
    }
  } else {
    in.code = unary_code(nd.op);
    in.a = slot_of(nd.a);
    in.k = nd.k;
  }
  return in;
}

}  // namespace

Program::Program(const Graph& g, const std::vector<int>& roots, int n, int m)
    : n_(n), m_(m), outputs_(static_cast<int>(roots.size())) {
  const int N = g.size();
  // Reachable nodes and their uses as operands; operands always have smaller ids than their
  // users (the graph is built bottom-up), so id order is a topological order.
  std::vector<char> live(static_cast<std::size_t>(N), 0);
  std::vector<int> uses(static_cast<std::size_t>(N), 0), root_of(static_cast<std::size_t>(N), 0);
  for (int r : roots) {
    live[r] = 1;
    ++root_of[r];
  }
  for (int id = N - 1; id >= 0; --id) {
    if (!live[id]) continue;
    const Node& nd = g[id];
    for (int opnd : {nd.a, nd.b})
      if (opnd >= 0) {
        live[opnd] = 1;
        ++uses[opnd];
      }
  }
  // Instructions in id order; the last instruction reading each node frees its register.
  std::vector<int> order;
  for (int id = 0; id < N; ++id)
    if (live[id] && !leaf(g[id])) order.push_back(id);
  std::vector<int> last(static_cast<std::size_t>(N), -1);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Node& nd = g[order[i]];
    for (int opnd : {nd.a, nd.b})
      if (opnd >= 0) last[opnd] = static_cast<int>(i);
  }
  std::vector<int> reg(static_cast<std::size_t>(N), -1);
  std::vector<int> free_regs;
  auto slot_of = [&](int id) {
    const Node& nd = g[id];
    return nd.op == Op::Var ? nd.k : n + m + reg[id];
  };
  auto direct_output = [&](int id) {  // a root read by nothing else: computed into the output
    if (uses[id] != 0 || root_of[id] != 1) return -1;
    for (std::size_t o = 0; o < roots.size(); ++o)
      if (roots[o] == id) return static_cast<int>(o);
    return -1;
  };
  for (std::size_t i = 0; i < order.size(); ++i) {
    const int id = order[i];
    const Node& nd = g[id];
    Instr in = operation(g, nd, slot_of);
    // The destination is chosen before the operands' registers are released, so an instruction
    // never writes over its own operands (the dual operators build their result in place).
    if (const int o = direct_output(id); o >= 0) {
      in.dst = -1 - o;
    } else {
      if (free_regs.empty()) {
        reg[id] = temps_++;
      } else {
        reg[id] = free_regs.back();
        free_regs.pop_back();
      }
      in.dst = reg[id];
    }
    code_.push_back(in);
    std::set<int> done;
    for (int opnd : {nd.a, nd.b})
      if (opnd >= 0 && !leaf(g[opnd]) && last[opnd] == static_cast<int>(i) && root_of[opnd] == 0 &&
          done.insert(opnd).second)
        free_regs.push_back(reg[opnd]);
  }
  // Outputs not computed in place: variables, constants and nodes that are also operands or
  // roots of several outputs.
  for (std::size_t o = 0; o < roots.size(); ++o) {
    const int id = roots[o];
    const Node& nd = g[id];
    if (!leaf(nd) && direct_output(id) >= 0) continue;
    Instr in{Code::Copy, -1 - static_cast<int>(o), -1, -1, 0, 0.0};
    if (nd.op == Op::Const) {
      in.code = Code::Const;
      in.c = nd.value;
    } else {
      in.a = slot_of(id);
    }
    code_.push_back(in);
  }
}

}  // namespace marsyn::equations
