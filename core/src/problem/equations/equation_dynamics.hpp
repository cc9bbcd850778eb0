#pragma once
// A dynamics model written as equations (docs/problem-format.md, "Dynamics as equations"):
// parsed once, compiled into one Program for the vector field and one per footprint, and
// evaluated through DynamicsModel for every scalar type of the interface.
#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "marsyn/dynamics.hpp"
#include "program.hpp"

namespace marsyn::equations {

struct EquationSpec {
  struct Entry {
    std::string name, text;
  };
  std::vector<std::string> states, inputs;
  std::vector<std::pair<std::string, double>> constants;  // values after per-agent overrides
  std::vector<Entry> definitions;                         // optional named sub-expressions, in order
  std::vector<Entry> field;                               // one per state (any order)
  struct Footprint {
    std::string name;
    std::array<std::string, 2> text;
  };
  std::vector<Footprint> footprints;
  // States the model turns freely in (`periodic: [theta]`): each may appear only inside sin, cos
  // and tan of a whole multiple of itself plus terms without it, so that the field and every
  // footprint are 2 pi-periodic in it by construction.
  std::vector<std::string> periodic;
};

// What went wrong and where: the part of the spec (`section`: "states", "inputs", "constants",
// "definitions", "field", "footprints"), the entry's index in it (-1: the section itself),
// the component of a footprint (0 or 1), and the offset in the expression when there is one.
class EquationError : public std::runtime_error {
 public:
  EquationError(std::string section, int index, const std::string& message, int component = 0,
                long offset = -1)
      : std::runtime_error(message), section_(std::move(section)), index_(index), component_(component), offset_(offset) {}
  const std::string& section() const { return section_; }
  int index() const { return index_; }
  int component() const { return component_; }
  long offset() const { return offset_; }  // -1: not inside an expression

 private:
  std::string section_;
  int index_, component_;
  long offset_;
};

class EquationDynamics final : public DynamicsModel<EquationDynamics> {
 public:
  // Throws EquationError.
  explicit EquationDynamics(const EquationSpec& spec);

  std::string type() const override { return type_; }
  int state_dim() const override { return static_cast<int>(spec_.states.size()); }
  int input_dim() const override { return static_cast<int>(spec_.inputs.size()); }
  std::vector<std::string> state_names() const override { return spec_.states; }
  std::vector<std::string> input_names() const override { return spec_.inputs; }
  std::vector<bool> field_independent_of() const override { return independent_; }
  std::vector<std::string> footprints() const override;
  std::vector<bool> periodic() const override { return periodic_; }

  template <class S>
  void vector_field(const S* x, const S* u, S* dx) const {
    field_.run(x, u, dx);
  }
  template <class S>
  void footprint_point(int which, const S* x, S* p) const {
    if (which >= 0 && which < static_cast<int>(footprint_programs_.size()))
      footprint_programs_[static_cast<std::size_t>(which)].run(x, static_cast<const S*>(nullptr), p);
  }

  const Program& field_program() const { return field_; }
  const EquationSpec& spec() const { return spec_; }

 private:
  EquationSpec spec_;
  std::string type_;
  Program field_;
  std::vector<Program> footprint_programs_;
  std::vector<bool> independent_;
  std::vector<bool> periodic_;
};

}  // namespace marsyn::equations
