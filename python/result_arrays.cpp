#include "result_arrays.hpp"

#include <pybind11/stl.h>

#include "numpy_arrays.hpp"

namespace marsyn::python {

py::dict period_enclosures(const Controller& controller) {
  const auto& es = controller.period_enclosures();
  const auto E = static_cast<py::ssize_t>(es.size());
  std::vector<Eigen::VectorXd> slo, shi, wlo, whi;
  py::array_t<int> step(E);
  py::array_t<double> t0(E), t1(E);
  for (py::ssize_t i = 0; i < E; ++i) {
    const auto& e = es[static_cast<size_t>(i)];
    step.mutable_at(i) = e.step;
    t0.mutable_at(i) = e.t0;
    t1.mutable_at(i) = e.t1;
    slo.push_back(e.state.lo);
    shi.push_back(e.state.hi);
    wlo.push_back(e.workspace.lo);
    whi.push_back(e.workspace.hi);
  }
  py::dict d;
  d["step"] = step;
  d["t0"] = t0;
  d["t1"] = t1;
  d["state_lo"] = matrix(slo, controller.state_dim());
  d["state_hi"] = matrix(shi, controller.state_dim());
  d["workspace_lo"] = matrix(wlo, 2);
  d["workspace_hi"] = matrix(whi, 2);
  return d;
}

#ifdef MARSYN_HAVE_PLANNING
namespace {

py::array_t<double> times(std::size_t count, double tau) {
  py::array_t<double> t(static_cast<py::ssize_t>(count));
  for (std::size_t k = 0; k < count; ++k) t.mutable_at(static_cast<py::ssize_t>(k)) = static_cast<double>(k) * tau;
  return t;
}

// StepMargins uses 1e300 for "the problem has no such requirement"; numpy users get inf, which
// compares and plots as "unconstrained" instead of a huge finite number.
double margin(double m) { return m >= 1e299 ? INFINITY : m; }

// {min, obstacle, collision, formation}, each (len,).
py::dict parts(const std::vector<StepMargins>& ms) {
  const auto n = static_cast<py::ssize_t>(ms.size());
  py::array_t<double> lo(n), ob(n), co(n), fo(n);
  for (py::ssize_t i = 0; i < n; ++i) {
    const StepMargins& m = ms[static_cast<size_t>(i)];
    lo.mutable_at(i) = margin(m.min());
    ob.mutable_at(i) = margin(m.obstacle);
    co.mutable_at(i) = margin(m.collision);
    fo.mutable_at(i) = margin(m.formation);
  }
  py::dict d;
  d["min"] = lo;
  d["obstacle"] = ob;
  d["collision"] = co;
  d["formation"] = fo;
  return d;
}

void add_change(py::list& out, const std::string& agent, const char* what, py::object given, py::object used) {
  py::dict c;
  c["agent"] = agent.empty() ? py::object(py::none()) : py::object(py::str(agent));
  c["what"] = what;
  c["given"] = std::move(given);
  c["used"] = std::move(used);
  out.append(c);
}

bool same(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return a.size() == b.size() && a == b; }

}  // namespace

py::dict tubes(const SolveOutcome& o) {
  py::dict out;
  const auto& nominal = o.plan.nominal;
  for (std::size_t i = 0; i < o.problem.agents.size() && i < nominal.size(); ++i) {
    const AgentSpec& a = o.problem.agents[i];
    std::vector<Eigen::VectorXd> lo, hi;
    for (const auto& x : nominal[i].x) {
      lo.push_back(x - a.tube.eps);
      hi.push_back(x + a.tube.eps);
    }
    py::dict t;
    t["t"] = times(nominal[i].x.size(), o.problem.tau);
    t["nominal"] = matrix(nominal[i].x, a.n());
    t["lo"] = matrix(lo, a.n());
    t["hi"] = matrix(hi, a.n());
    t["eps"] = vector(a.tube.eps);
    const auto& ctrl = i < o.agents.size() ? o.agents[i].track.controller : nullptr;
    t["enclosures"] = ctrl ? period_enclosures(*ctrl) : py::object(py::none());
    out[py::str(a.name)] = t;
  }
  return out;
}

py::list margins(const SolveOutcome& o) {
  py::list out;
  for (const auto& run : o.verification.kept) {
    py::dict r;
    r["label"] = run.label;
    r["satisfied"] = run.spec.satisfied;
    r["min_margin"] = margin(run.spec.min_margin);
    r["goal_margin"] = margin(run.spec.goal_margin);
    r["t"] = times(run.spec.per_step.size(), o.problem.tau);
    r["samples"] = parts(run.spec.per_step);
    py::array_t<double> dense_t(static_cast<py::ssize_t>(run.dense_t.size()));
    for (std::size_t q = 0; q < run.dense_t.size(); ++q) dense_t.mutable_at(static_cast<py::ssize_t>(q)) = run.dense_t[q];
    r["dense_t"] = dense_t;
    r["dense"] = parts(run.dense);
    out.append(r);
  }
  return out;
}

py::list search_changes(const Problem& given, const SolveOutcome& o) {
  py::list out;
  if (o.plan.horizon > 0 && o.plan.horizon != given.horizon)
    add_change(out, "", "horizon", py::int_(given.horizon), py::int_(o.plan.horizon));
  for (std::size_t i = 0; i < given.agents.size() && i < o.problem.agents.size(); ++i) {
    const AgentSpec& g = given.agents[i];
    const AgentSpec& u = o.problem.agents[i];
    const std::string used_tracker = i < o.agents.size() && !o.agents[i].tracker.empty() ? o.agents[i].tracker : u.tracker.name;
    if (used_tracker != g.tracker.name) add_change(out, g.name, "tracker", py::str(g.tracker.name), py::str(used_tracker));
    else if (u.tracker.params.values() != g.tracker.params.values())
      add_change(out, g.name, "tracker params", py::cast(g.tracker.params.values()), py::cast(u.tracker.params.values()));
    if (!same(g.tube.eps, u.tube.eps)) add_change(out, g.name, "eps", vector(g.tube.eps), vector(u.tube.eps));
    for (const auto& f : u.fields.items)  // the trackers' own fields (abcd's grid)
      if (const Eigen::VectorXd was = g.fields.value(f.name); !same(was, f.value))
        add_change(out, g.name, f.name.c_str(), vector(was), vector(f.value));
  }
  return out;
}
#endif

}  // namespace marsyn::python
