#pragma once
// A control system x' = f(x, u) + w with w in the box [-W, W] (paper Sec. 2, additive
// disturbance). Models write the vector field once, as a template over the scalar type, by
// deriving from DynamicsModel<Model>; the same definition then serves simulation (double),
// exact Jacobians (DualD) and sound enclosures (Interval, DualI).
#include <string>
#include <vector>

#include "marsyn/scalar.hpp"

namespace marsyn {

class Dynamics {
 public:
  virtual ~Dynamics() = default;

  virtual std::string type() const = 0;  // the plugin name, e.g. "unicycle"
  virtual int state_dim() const = 0;
  virtual int input_dim() const = 0;
  virtual std::vector<std::string> state_names() const = 0;
  virtual std::vector<std::string> input_names() const = 0;

  // dx = f(x, u): the disturbance-free continuous vector field.
  virtual void field(const double* x, const double* u, double* dx) const = 0;
  virtual void field(const DualD* x, const DualD* u, DualD* dx) const = 0;
  virtual void field(const Interval* x, const Interval* u, Interval* dx) const = 0;
  virtual void field(const DualI* x, const DualI* u, DualI* dx) const = 0;

  // State coordinates f does not read. Translating the state along them translates every
  // solution by the same amount, which trackers exploit to reuse successor boxes.
  virtual std::vector<bool> field_independent_of() const {
    return std::vector<bool>(static_cast<size_t>(state_dim()), false);
  }

  // Optional named workspace footprint (a point in the plane computed from the state, e.g. the
  // crane's pendulum tip). Returns the number of workspace coordinates, 0 when the model has
  // no footprint of that name.
  virtual std::vector<std::string> footprints() const { return {}; }
  virtual void footprint(int /*which*/, const double* /*x*/, double* /*p*/) const {}
  virtual void footprint(int /*which*/, const DualD* /*x*/, DualD* /*p*/) const {}
  virtual void footprint(int /*which*/, const Interval* /*x*/, Interval* /*p*/) const {}
};

// CRTP adapter: Model provides
//   template <class S> void vector_field(const S* x, const S* u, S* dx) const;
// and optionally
//   template <class S> void footprint_point(int which, const S* x, S* p) const;
template <class Model>
class DynamicsModel : public Dynamics {
 public:
  void field(const double* x, const double* u, double* dx) const final { self().vector_field(x, u, dx); }
  void field(const DualD* x, const DualD* u, DualD* dx) const final { self().vector_field(x, u, dx); }
  void field(const Interval* x, const Interval* u, Interval* dx) const final {
    self().vector_field(x, u, dx);
  }
  void field(const DualI* x, const DualI* u, DualI* dx) const final { self().vector_field(x, u, dx); }

 public:
  // Models without a footprint inherit this no-op; those with one shadow it.
  template <class S>
  void footprint_point(int, const S*, S*) const {}

  void footprint(int which, const double* x, double* p) const override {
    self().footprint_point(which, x, p);
  }
  void footprint(int which, const DualD* x, DualD* p) const override {
    self().footprint_point(which, x, p);
  }
  void footprint(int which, const Interval* x, Interval* p) const override {
    self().footprint_point(which, x, p);
  }

 private:
  const Model& self() const { return static_cast<const Model&>(*this); }
};

}  // namespace marsyn
