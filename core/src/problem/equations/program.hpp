#pragma once
// An equation model compiled once into a flat instruction list (SSA with register reuse),
// evaluated by one template for every scalar type. Each instruction is one operation of the
// written expression, in the written order, on the overloads scalar_ops.hpp names: the same
// arithmetic a C++ plugin performs, so point values and derivatives are bit-identical to a plugin
// that writes the same expression, and interval results are enclosures by construction (every
// step is a sound interval operation on enclosures of its operands).
#include <algorithm>
#include <cstdint>
#include <new>
#include <type_traits>
#include <vector>

#include "expression.hpp"
#include "scalar_ops.hpp"

namespace marsyn::equations {

class Program {
 public:
  enum class Code : std::uint8_t {
    Add, Sub, Mul, Div,              // slot op slot
    AddRC, SubRC, MulRC, DivRC,      // slot op constant
    AddCR, SubCR, MulCR, DivCR,      // constant op slot
    Neg, Sin, Cos, Tan, Exp, Log, Sqrt, Atan, Pow,
    Copy, Const                      // an output that is a variable, a shared node or a constant
  };
  struct Instr {
    Code code;
    int dst;     // >= 0: temporary register; < 0: output -1 - dst
    int a, b;    // slots: [0, n) states, [n, n + m) inputs, then temporaries
    int k;       // Pow exponent
    double c;    // constant operand
  };

  Program() = default;
  // Compiles the nodes `roots` (one per output) of `g`; variables 0..n-1 are read from x,
  // n..n+m-1 from u.
  Program(const Graph& g, const std::vector<int>& roots, int n, int m);

  int outputs() const { return outputs_; }
  int temporaries() const { return temps_; }
  const std::vector<Instr>& code() const { return code_; }

  template <class S>
  void run(const S* x, const S* u, S* out) const {
    static_assert(std::is_trivially_destructible_v<S>,
                  "registers are raw storage");
    constexpr int kStackTemps = std::max<int>(8, static_cast<int>(32768 / sizeof(S)));
    constexpr int kStackSlots = 96;
    alignas(S) unsigned char stack_regs[sizeof(S) * kStackTemps];
    const S* stack_slots[kStackSlots];
    std::vector<S> heap_regs;
    std::vector<const S*> heap_slots;
    S* reg = reinterpret_cast<S*>(stack_regs);
    if (temps_ > kStackTemps) {
      heap_regs.resize(static_cast<std::size_t>(temps_));
      reg = heap_regs.data();
    }
    const S** slot = stack_slots;
    if (n_ + m_ + temps_ > kStackSlots) {
      heap_slots.resize(static_cast<std::size_t>(n_ + m_ + temps_));
      slot = heap_slots.data();
    }
    for (int i = 0; i < n_; ++i) slot[i] = x + i;
    for (int j = 0; j < m_; ++j) slot[n_ + j] = u + j;
    for (int t = 0; t < temps_; ++t) slot[n_ + m_ + t] = reg + t;

    for (const Instr& in : code_) {
      S* d = in.dst >= 0 ? reg + in.dst : out + (-1 - in.dst);
      const S& a = *slot[in.a >= 0 ? in.a : 0];
      switch (in.code) {
        case Code::Add: ::new (d) S(a + *slot[in.b]); break;
        case Code::Sub: ::new (d) S(a - *slot[in.b]); break;
        case Code::Mul: ::new (d) S(a * *slot[in.b]); break;
        case Code::Div: ::new (d) S(a / *slot[in.b]); break;
        case Code::AddRC: ::new (d) S(a + in.c); break;
        case Code::SubRC: ::new (d) S(a - in.c); break;
        case Code::MulRC: ::new (d) S(a * in.c); break;
        case Code::DivRC: ::new (d) S(a / in.c); break;
        case Code::AddCR: ::new (d) S(in.c + a); break;
        case Code::SubCR: ::new (d) S(in.c - a); break;
        case Code::MulCR: ::new (d) S(in.c * a); break;
        case Code::DivCR: ::new (d) S(in.c / a); break;
        case Code::Neg: ::new (d) S(-a); break;
        case Code::Sin: ::new (d) S(ops::fn_sin(a)); break;
        case Code::Cos: ::new (d) S(ops::fn_cos(a)); break;
        case Code::Tan: ::new (d) S(ops::fn_tan(a)); break;
        case Code::Exp: ::new (d) S(ops::fn_exp(a)); break;
        case Code::Log: ::new (d) S(ops::fn_log(a)); break;
        case Code::Sqrt: ::new (d) S(ops::fn_sqrt(a)); break;
        case Code::Atan: ::new (d) S(ops::fn_atan(a)); break;
        case Code::Pow: ::new (d) S(ops::fn_pow(a, in.k)); break;
        case Code::Copy: ::new (d) S(a); break;
        case Code::Const: ::new (d) S(in.c); break;
      }
    }
  }

 private:
  int n_ = 0, m_ = 0, temps_ = 0, outputs_ = 0;
  std::vector<Instr> code_;
};

}  // namespace marsyn::equations
