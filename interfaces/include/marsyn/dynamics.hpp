#pragma once
// A control system x' = f(x, u) + w with w in the box [-W, W] (paper Sec. 2, additive
// disturbance). Models write the vector field once, as a template over the scalar type, by
// deriving from DynamicsModel<Model>; the same definition then serves simulation (double),
// exact Jacobians (DualD) and Hessians (DualD2), and sound enclosures (Interval, DualI; FastInterval, DualFI, DualFI2 in hot
// loops, see fast_interval.hpp).
#include <stdexcept>
#include <string>
#include <vector>

#include "marsyn/lanes.hpp"
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
  // The same enclosures with FastInterval (valid in round-to-nearest). DynamicsModel evaluates
  // the templated field directly; a Dynamics written by hand inherits these conversions through
  // the Interval overloads, which are just as sound, only slower.
  virtual void field(const FastInterval* x, const FastInterval* u, FastInterval* dx) const;
  virtual void field(const DualFI* x, const DualFI* u, DualFI* dx) const;
  // Four states at once (lanes.hpp: the verification's runs in lockstep). A Dynamics written by
  // hand inherits a lane-by-lane loop over the double field.
  virtual void field(const Lanes* x, const Lanes* u, Lanes* dx) const;
  // Exact second derivatives (forward over forward AD) for second-order planners. DynamicsModel
  // provides them; a Dynamics written by hand reports false here, and planners then difference
  // first derivatives instead.
  virtual bool has_second_order() const { return false; }
  virtual void field(const DualD2* /*x*/, const DualD2* /*u*/, DualD2* /*dx*/) const {
    throw std::logic_error("this dynamics model has no second-order (DualD2) field");
  }
  // Hessian enclosures over boxes (DualFI2, valid in round-to-nearest like FastInterval), for
  // second-order remainders. DynamicsModel provides them; a Dynamics written by hand reports
  // false and its users fall back to first-order (Jacobian) enclosures.
  virtual bool has_interval_second_order() const { return false; }
  virtual void field(const DualFI2* /*x*/, const DualFI2* /*u*/, DualFI2* /*dx*/) const {
    throw std::logic_error("this dynamics model has no interval second-order (DualFI2) field");
  }

  // State coordinates f does not read. Translating the state along them translates every
  // solution by the same amount, which trackers exploit to reuse successor boxes.
  virtual std::vector<bool> field_independent_of() const {
    return std::vector<bool>(static_cast<size_t>(state_dim()), false);
  }

  // Coordinates the model is 2 pi-periodic in (angles: a heading, a pendulum's angle): f and
  // every footprint take the same value at x and at x + 2 pi e_i. Problems may then leave them
  // free (`any`) and state goals on the circle; the method works on the lift (the angle as a real
  // number) and a controller reads a measured angle on the branch nearest its step's reference
  // (docs/problem-format.md "Periodic coordinates", docs/soundness.md). The declaration is the
  // model author's; the dynamics tests check it at random states.
  virtual std::vector<bool> periodic() const { return std::vector<bool>(static_cast<size_t>(state_dim()), false); }

  // Optional named workspace footprint (a point in the plane computed from the state, e.g. the
  // crane's pendulum tip). Returns the number of workspace coordinates, 0 when the model has
  // no footprint of that name.
  virtual std::vector<std::string> footprints() const { return {}; }
  virtual void footprint(int /*which*/, const double* /*x*/, double* /*p*/) const {}
  virtual void footprint(int /*which*/, const DualD* /*x*/, DualD* /*p*/) const {}
  virtual void footprint(int /*which*/, const Interval* /*x*/, Interval* /*p*/) const {}
  virtual void footprint(int /*which*/, const DualD2* /*x*/, DualD2* /*p*/) const {}
};

inline void Dynamics::field(const FastInterval* x, const FastInterval* u, FastInterval* dx) const {
  const int n = state_dim(), m = input_dim();
  std::vector<Interval> xi(static_cast<std::size_t>(n)), ui(static_cast<std::size_t>(m)), di(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) xi[i] = x[i].to_interval();
  for (int j = 0; j < m; ++j) ui[j] = u[j].to_interval();
  field(xi.data(), ui.data(), di.data());
  for (int i = 0; i < n; ++i) dx[i] = FastInterval(di[i]);
}

inline void Dynamics::field(const DualFI* x, const DualFI* u, DualFI* dx) const {
  const int n = state_dim(), m = input_dim();
  auto to_i = [](const DualFI& a) {
    DualI r(a.v.to_interval());
    r.n = a.n;
    for (int k = 0; k < a.n; ++k) r.d[k] = a.d[k].to_interval();
    return r;
  };
  std::vector<DualI> xi(static_cast<std::size_t>(n)), ui(static_cast<std::size_t>(m)), di(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) xi[i] = to_i(x[i]);
  for (int j = 0; j < m; ++j) ui[j] = to_i(u[j]);
  field(xi.data(), ui.data(), di.data());
  for (int i = 0; i < n; ++i) {
    DualFI r{FastInterval(di[i].v)};
    r.n = di[i].n;
    for (int k = 0; k < di[i].n; ++k) r.d[k] = FastInterval(di[i].d[k]);
    dx[i] = r;
  }
}

inline void Dynamics::field(const Lanes* x, const Lanes* u, Lanes* dx) const {
  const int n = state_dim(), m = input_dim();
  std::vector<double> xs(static_cast<std::size_t>(n)), us(static_cast<std::size_t>(m)), ds(static_cast<std::size_t>(n));
  for (int l = 0; l < Lanes::kWidth; ++l) {
    for (int i = 0; i < n; ++i) xs[i] = x[i][l];
    for (int j = 0; j < m; ++j) us[j] = u[j][l];
    field(xs.data(), us.data(), ds.data());
    for (int i = 0; i < n; ++i) dx[i][l] = ds[i];
  }
}

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
  void field(const FastInterval* x, const FastInterval* u, FastInterval* dx) const final {
    self().vector_field(x, u, dx);
  }
  void field(const DualFI* x, const DualFI* u, DualFI* dx) const final { self().vector_field(x, u, dx); }
  void field(const Lanes* x, const Lanes* u, Lanes* dx) const final { self().vector_field(x, u, dx); }
  bool has_second_order() const final { return true; }
  void field(const DualD2* x, const DualD2* u, DualD2* dx) const final { self().vector_field(x, u, dx); }
  bool has_interval_second_order() const final { return true; }
  void field(const DualFI2* x, const DualFI2* u, DualFI2* dx) const final { self().vector_field(x, u, dx); }

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
  void footprint(int which, const DualD2* x, DualD2* p) const override { self().footprint_point(which, x, p); }

 private:
  const Model& self() const { return static_cast<const Model&>(*this); }
};

}  // namespace marsyn
