// The `marsyn` Python module (docs/python.md): thin bindings over core's public API
// (core/include/marsyn/core/*.hpp). Problems load with the same validation and located errors as
// the CLI (marsyn.ConfigError); plans, tracking results and solve outcomes come back as dicts with
// states as numpy arrays; controllers evaluate C(x, k) vectorised over many states.
//
// Threads: every long call releases the GIL; progress lines reach the Python callback (or the
// "marsyn" logger) with the GIL re-acquired, from whichever thread produced them.
#include <dlfcn.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <optional>

#include "marsyn/core/verification/closed_loop.hpp"
#include "marsyn/core/problem/config_error.hpp"
#include "marsyn/core/planning/solver_progress.hpp"
#include "marsyn/core/planning/plan_io.hpp"
#include "marsyn/core/plugins/plugin_registry.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/core/problem/problem_summary.hpp"
#include "marsyn/core/verification/spec_monitor.hpp"
#include "marsyn/error.hpp"
#include "marsyn/tracker.hpp"
#include "numpy_arrays.hpp"
#include "result_arrays.hpp"
#ifdef MARSYN_HAVE_PLANNING
#include "marsyn/core/report/output_folder.hpp"
#include "marsyn/core/report/result_json.hpp"
#include "marsyn/core/report/solve_outputs.hpp"
#include "marsyn/core/planning/plan.hpp"
#include "marsyn/core/setup.hpp"
#endif

namespace py = pybind11;
namespace fs = std::filesystem;
using namespace marsyn;

namespace {

// A loaded problem; its registry keeps the plugin libraries loaded.
struct PyProblem {
  std::shared_ptr<LoadedProblem> lp;
};

// A controller and whatever keeps its plugin library loaded (the tracker or the registry).
struct PyController {
  std::shared_ptr<const Controller> c;
  std::shared_ptr<const void> keep;
  std::string agent;
  // The controller's destructor is code in its plugin library: release it while `keep` still
  // holds that library (members are destroyed in reverse order, `keep` before `c`).
  ~PyController() { c.reset(); }
  PyController() = default;
  PyController(std::shared_ptr<const Controller> ctl, std::shared_ptr<const void> k, std::string name)
      : c(std::move(ctl)), keep(std::move(k)), agent(std::move(name)) {}
  PyController(const PyController&) = default;
  PyController& operator=(const PyController&) = default;
};

using python::matrix;
using python::vector;

Eigen::VectorXd to_eigen(const py::handle& h) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h);
  if (!a || a.ndim() != 1) throw py::value_error("expected a 1-d array of numbers");
  Eigen::VectorXd v(a.shape(0));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) v[i] = a.at(i);
  return v;
}

// Progress lines to `log` (a callable) or, when None, to logging.getLogger("marsyn").info.
std::function<void(const std::string&)> progress(py::object log) {
  if (log.is_none()) log = py::module_::import("logging").attr("getLogger")("marsyn").attr("info");
  // The callable is released with the GIL held, whichever thread drops the last copy.
  std::shared_ptr<py::object> holder(new py::object(std::move(log)), [](py::object* p) {
    py::gil_scoped_acquire gil;
    delete p;
  });
  return [holder](const std::string& line) {
    py::gil_scoped_acquire gil;
    try {
      (*holder)(line);
    } catch (py::error_already_set& e) {
      e.discard_as_unraisable("marsyn progress callback");
    }
  };
}

py::dict agent_dict(const Problem& pb, const AgentSpec& a) {
  py::dict d;
  d["name"] = a.name;
  d["dynamics"] = a.dynamics_type;
  d["state_names"] = a.dynamics->state_names();
  d["input_names"] = a.dynamics->input_names();
  d["x0"] = vector(a.x0);
  d["x0_radius"] = vector(a.x0_radius.size() ? a.x0_radius : Eigen::VectorXd::Zero(a.n()));
  d["radius"] = a.radius;  // the body's half-width, added to its clearances
  py::list bodies;  // every body when the agent lists them (its own point first): name and radius
  if (!a.body.empty()) {
    py::dict b;
    b["name"] = a.body;
    b["radius"] = a.radius;
    bodies.append(b);
  }
  for (const auto& e : pb.extra_bodies)
    if (e.spec.n() == a.n() && pb.agents[static_cast<std::size_t>(e.agent)].name == a.name) {
      py::dict b;
      b["name"] = e.body;
      b["radius"] = e.spec.radius;
      bodies.append(b);
    }
  d["bodies"] = bodies;
  d["goal"] = py::make_tuple(vector(a.goal.lo), vector(a.goal.hi));
  d["state_bounds"] = py::make_tuple(vector(a.state_bounds.lo), vector(a.state_bounds.hi));
  d["input_bounds"] = py::make_tuple(vector(a.input_bounds.lo), vector(a.input_bounds.hi));
  d["w"] = vector(a.tube.w);  // W's largest value over X and U
  if (a.tube.state_dependent()) {  // W(x, u) = w_base + sum of w_per[name] |name|
    d["w_base"] = vector(a.tube.w_base);
    py::dict per;
    for (const auto& g : a.tube.w_growth) per[g.name.c_str()] = vector(g.gain);
    d["w_per"] = per;
  }
  d["eps"] = vector(a.tube.eps);
  for (const auto& f : a.fields.items) d[f.name.c_str()] = vector(f.value);  // the trackers' own (abcd: eta_x, eta_u)
  d["tracker"] = a.tracker.name;  // resolved per agent (never "auto")
  return d;
}

// {agent: {"x": (T+1, n), "u": (T, m)}}
py::dict nominal_dict(const Problem& pb, const std::vector<NominalTrajectory>& nominal) {
  py::dict d;
  for (size_t i = 0; i < nominal.size() && i < pb.agents.size(); ++i) {
    py::dict a;
    a["x"] = matrix(nominal[i].x, pb.agents[i].n());
    a["u"] = matrix(nominal[i].u, pb.agents[i].m());
    d[py::str(pb.agents[i].name)] = a;
  }
  return d;
}

// A plan given as a dict from plan()/solve() ({"agents": {...}} or the agents dict itself), or a
// plan.json path; None means "plan now" where the caller allows it.
std::vector<NominalTrajectory> nominal_from(const Problem& pb, const py::object& plan) {
  if (py::isinstance<py::str>(plan) || py::hasattr(plan, "__fspath__"))
    return planning::read_plan_json(py::str(py::module_::import("os").attr("fspath")(plan)).cast<std::string>(), pb);
  if (!py::isinstance<py::dict>(plan)) throw py::type_error("plan: expected a dict from marsyn.plan/solve or a plan.json path");
  py::dict d = plan.cast<py::dict>();
  if (d.contains("nominal") && py::isinstance<py::dict>(d["nominal"])) d = d["nominal"].cast<py::dict>();  // solve()
  else if (d.contains("agents") && py::isinstance<py::dict>(d["agents"])) d = d["agents"].cast<py::dict>();  // plan()
  std::vector<NominalTrajectory> out;
  for (const auto& a : pb.agents) {
    if (!d.contains(a.name.c_str())) throw py::key_error("plan has no agent '" + a.name + "'");
    py::dict ad = d[a.name.c_str()].cast<py::dict>();
    NominalTrajectory t;
    t.agent = a.name;
    const auto x = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(ad["x"]);
    const auto u = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(ad["u"]);
    if (!x || x.ndim() != 2 || x.shape(1) != a.n()) throw py::value_error("plan: " + a.name + "'s x must be (T+1, n)");
    if (!u || u.ndim() != 2 || (u.shape(0) > 0 && u.shape(1) != a.m()) || u.shape(0) + 1 != x.shape(0))
      throw py::value_error("plan: " + a.name + "'s u must be (T, m)");
    for (py::ssize_t r = 0; r < x.shape(0); ++r) {
      Eigen::VectorXd v(a.n());
      for (int c = 0; c < a.n(); ++c) v[c] = x.at(r, c);
      t.x.push_back(v);
    }
    for (py::ssize_t r = 0; r < u.shape(0); ++r) {
      Eigen::VectorXd v(a.m());
      for (int c = 0; c < a.m(); ++c) v[c] = u.at(r, c);
      t.u.push_back(v);
    }
    out.push_back(std::move(t));
  }
  return out;
}

py::dict stats_dict(const TrackerStats& s) {
  py::dict d;
  d["state_input_pairs"] = s.state_input_pairs;
  d["boxes_computed"] = s.boxes_computed;
  d["abstraction_time_s"] = s.abstraction_time_s;
  d["synthesis_time_s"] = s.synthesis_time_s;
  d["peak_memory_bytes"] = s.peak_memory_bytes;
  // The tracker's own figures (abcd: tube_cells, winning_cells_per_step, initial_state_winning).
  for (const auto& f : s.figures) d[f.name.c_str()] = std::visit([](const auto& v) { return py::cast(v); }, f.value);
  return d;
}

py::object json_to_python(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

// C(x, k) over many states: x of shape (N, n) or (n,), k an int or N ints. Returns (u, status):
// u of shape (N, m) (NaN where there is no input), status int8 0 ok, 1 outside domain, 2 outside horizon.
py::tuple evaluate(const PyController& pc, py::array_t<double, py::array::c_style | py::array::forcecast> x, py::object k) {
  const Controller& c = *pc.c;
  const int n = c.state_dim(), m = c.input_dim();
  const bool single = x.ndim() == 1;
  if (!(x.ndim() == 2 || single) || x.shape(x.ndim() - 1) != n)
    throw py::value_error("x: expected shape (N, " + std::to_string(n) + ") or (" + std::to_string(n) + ",)");
  const py::ssize_t N = single ? 1 : x.shape(0);
  py::array_t<long long, py::array::c_style | py::array::forcecast> ks;
  if (py::isinstance<py::int_>(k)) {
    ks = py::array_t<long long, py::array::c_style | py::array::forcecast>(N);
    for (py::ssize_t i = 0; i < N; ++i) ks.mutable_at(i) = k.cast<long long>();
  } else {
    ks = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(k);
    if (!ks || ks.ndim() != 1 || ks.shape(0) != N) throw py::value_error("k: expected an int or N ints");
  }
  py::array_t<double> u({N, static_cast<py::ssize_t>(m)});
  py::array_t<std::int8_t> status(N);
  const double* xp = x.data();
  const long long* kp = ks.data();
  double* up = u.mutable_data();
  std::int8_t* sp = status.mutable_data();
  {
    py::gil_scoped_release release;
    for (py::ssize_t i = 0; i < N; ++i) {
      const long long kk = kp[i];
      const int ki = kk < std::numeric_limits<int>::min() ? std::numeric_limits<int>::min()
                     : kk > std::numeric_limits<int>::max() ? std::numeric_limits<int>::max()
                                                            : static_cast<int>(kk);
      const ControlStatus s = c.input(xp + i * n, ki, up + i * m);
      sp[i] = static_cast<std::int8_t>(s);
      if (s != ControlStatus::Ok)
        for (int j = 0; j < m; ++j) up[i * m + j] = NAN;
    }
  }
  if (single) return py::make_tuple(u[py::int_(0)], status[py::int_(0)]);
  return py::make_tuple(u, status);
}

std::vector<std::shared_ptr<const Controller>> controllers_from(const Problem& pb, const py::object& obj,
                                                                std::vector<std::shared_ptr<const void>>& keep,
                                                                const std::shared_ptr<LoadedProblem>& lp) {
  std::vector<std::shared_ptr<const Controller>> out;
  if (py::isinstance<py::str>(obj) || py::hasattr(obj, "__fspath__")) {
    const std::string dir = py::str(py::module_::import("os").attr("fspath")(obj)).cast<std::string>();
    // Each agent's controller through the tracker that wrote it (result.json beside the files,
    // else the agent's own), kept alive with the controllers.
    TrackerInstances trackers(lp->registry);
    out = read_agent_controllers(pb, trackers, dir);
    for (const auto& a : pb.agents) keep.push_back(trackers.get(a.tracker));
    for (const auto& [agent, name] : recorded_trackers(dir)) keep.push_back(trackers.get({name, {}}));
    return out;
  }
  if (py::isinstance<py::dict>(obj)) {
    py::dict d = obj.cast<py::dict>();
    for (const auto& a : pb.agents) {
      if (!d.contains(a.name.c_str())) throw py::key_error("controllers: no controller for agent '" + a.name + "'");
      const auto& pc = d[a.name.c_str()].cast<const PyController&>();
      out.push_back(pc.c);
      keep.push_back(pc.keep);
    }
    return out;
  }
  for (const auto& item : obj) {
    const auto& pc = item.cast<const PyController&>();
    out.push_back(pc.c);
    keep.push_back(pc.keep);
  }
  if (out.size() != pb.agents.size()) throw py::value_error("controllers: one per agent expected");
  return out;
}

// Plugins are found next to the module: in the build tree the build's plugin folder, installed
// PREFIX/lib/marsyn/plugins (the module lives in PREFIX/lib/pythonX.Y/...-packages).
void add_module_plugin_paths() {
  Dl_info info{};
  if (!dladdr(reinterpret_cast<void*>(&add_module_plugin_paths), &info) || !info.dli_fname) return;
  std::error_code ec;
  const fs::path here = fs::weakly_canonical(fs::path(info.dli_fname), ec).parent_path();
  std::vector<fs::path> candidates;
#ifdef MARSYN_BUILD_MODULE_DIR
  if (fs::weakly_canonical(fs::path(MARSYN_BUILD_MODULE_DIR), ec) == here) candidates.emplace_back(MARSYN_BUILD_PLUGIN_DIR);
#endif
  candidates.push_back(here / "../../marsyn/plugins");
  std::string path;
  if (const char* env = std::getenv("MARSYN_PLUGIN_PATH")) path = env;
  for (const auto& c : candidates)
    if (fs::is_directory(c, ec)) path += (path.empty() ? "" : ":") + fs::weakly_canonical(c, ec).string();
  if (!path.empty()) setenv("MARSYN_PLUGIN_PATH", path.c_str(), 1);
}

// marsyn.ConfigError and marsyn.ParamError, with the fields of their C++ originals.
void bind_errors(py::module_& m) {
  static py::handle config_error =
      py::exception<ConfigError>(m, "ConfigError", PyExc_ValueError).release();
  static py::handle param_error = py::exception<ParamError>(m, "ParamError", PyExc_ValueError).release();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ConfigError& e) {
      py::object ex = py::reinterpret_borrow<py::object>(config_error)(e.what());
      ex.attr("file") = e.file();
      ex.attr("line") = e.line();
      ex.attr("column") = e.column();
      ex.attr("path") = e.path();
      ex.attr("message") = e.message();
      PyErr_SetObject(config_error.ptr(), ex.ptr());
    } catch (const ParamError& e) {
      py::object ex = py::reinterpret_borrow<py::object>(param_error)(std::string("parameter ") + e.field() + ": " + e.what());
      ex.attr("field") = e.field();
      PyErr_SetObject(param_error.ptr(), ex.ptr());
    }
  });
}

// plugins(), Problem and load().
void bind_problem(py::module_& m) {
  m.def(
      "plugins",
      []() {
        PluginRegistry registry;
        py::list out;
        for (const auto& i : registry.plugins()) {
          py::dict d;
          d["kind"] = i.kind;
          d["name"] = i.name;
          d["summary"] = i.summary;
          d["library"] = i.library_path;
          py::list params;
          for (const auto& p : i.params) {
            py::dict pd;
            pd["name"] = p.name;
            pd["type"] = to_string(p.type);
            pd["default"] = p.default_value;
            pd["range"] = p.range;
            pd["doc"] = p.doc;
            params.append(pd);
          }
          d["params"] = params;
          out.append(d);
        }
        return out;
      },
      "Every plugin found (kind, name, summary, library, params), as `marsyn plugins --params`.");

  py::class_<PyProblem>(m, "Problem", "A loaded and validated problem (marsyn.load).")
      .def_property_readonly("name", [](const PyProblem& p) { return p.lp->problem.name; })
      .def_property_readonly("source", [](const PyProblem& p) { return p.lp->problem.source; })
      .def_property_readonly("horizon", [](const PyProblem& p) { return p.lp->problem.horizon; })
      .def_property_readonly("tau", [](const PyProblem& p) { return p.lp->problem.tau; })
      .def_property_readonly("planner", [](const PyProblem& p) { return p.lp->problem.planner.name; })
      .def_property_readonly("tracker", [](const PyProblem& p) { return p.lp->problem.tracker.name; },
                             "The top-level request: a tracker's name or 'auto'; each agent's is agents[i]['tracker'].")
      .def_property_readonly("agents",
                             [](const PyProblem& p) {
                               py::list l;
                               for (const auto& a : p.lp->problem.agents) l.append(agent_dict(p.lp->problem, a));
                               return l;
                             })
      .def_property_readonly("obstacles",
                             [](const PyProblem& p) {
                               py::list l;
                               for (const auto& o : p.lp->problem.obstacles) {
                                 std::vector<Eigen::VectorXd> v(o.vertices.begin(), o.vertices.end());
                                 py::dict d;
                                 d["name"] = o.name;
                                 d["vertices"] = matrix(v, 2);
                                 l.append(d);
                               }
                               return l;
                             },
                             "Each obstacle: name and vertices (k, 2), a convex polygon in workspace coordinates, "
                             "counter-clockwise.")
      .def("summary", [](const PyProblem& p) { return summarize(p.lp->problem, p.lp->trackers); },
           "The summary `marsyn check` prints.")
      .def("__repr__", [](const PyProblem& p) {
        return "<marsyn.Problem '" + p.lp->problem.name + "': " + std::to_string(p.lp->problem.agents.size()) + " agents, T=" +
               std::to_string(p.lp->problem.horizon) + ">";
      });

  m.def(
      "load",
      [](const py::object& path, const py::object& memory_budget) {
        const std::string file = py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
        LoadOptions lo;
        if (!memory_budget.is_none()) {
          const std::string text = py::str(memory_budget).cast<std::string>();
          const std::optional<double> bytes = parse_bytes(text);
          if (!bytes)
            throw py::value_error("memory_budget: expected a positive number of bytes such as 8e9 or '8G', got '" + text +
                                  "'");
          lo.memory_budget = {*bytes, "memory_budget"};
        }
        return PyProblem{std::make_shared<LoadedProblem>(load_problem(file, lo))};
      },
      py::arg("path"), py::arg("memory_budget") = py::none(),
      "Load and validate a problem file. memory_budget (bytes, or a string such as '2G'; default half of the physical "
      "memory) is what the trackers' and the planner's estimates are judged against, here and when this problem is "
      "tracked or solved. Bad input raises marsyn.ConfigError with the CLI's located message "
      "(attributes file, line, column, path, message).");
}

// Controller and read_controller().
void bind_controller(py::module_& m) {
  py::class_<PyController>(m, "Controller", "A synthesized controller C(x, k).")
      .def_property_readonly("state_dim", [](const PyController& c) { return c.c->state_dim(); })
      .def_property_readonly("input_dim", [](const PyController& c) { return c.c->input_dim(); })
      .def_property_readonly("horizon", [](const PyController& c) { return c.c->horizon(); },
                             "T (inputs for k = 0..T-1), or -1 for a time-invariant controller")
      .def_property_readonly("agent", [](const PyController& c) { return c.agent; })
      .def_property_readonly(
          "period_enclosures",
          [](const PyController& c) { return python::period_enclosures(*c.c); },
          "Sound enclosures of the closed loop between the samples (continuous-time guarantee; empty arrays when the "
          "tracker gives none): step, t0, t1 (E,), state_lo/state_hi (E, n), workspace_lo/workspace_hi (E, 2).")
      .def("input", &evaluate, py::arg("x"), py::arg("k"),
           "C(x, k) for x of shape (N, n) (or (n,)) and k an int or N ints. Returns (u, status): u (N, m) with NaN where "
           "there is no input, status int8: marsyn.OK, OUTSIDE_DOMAIN or OUTSIDE_HORIZON.")
      .def("__call__", &evaluate, py::arg("x"), py::arg("k"))
      .def("write", [](const PyController& c, const std::string& path) { c.c->write(path); }, py::arg("path"),
           "Write the controller file (the tracker's format).")
      .def(
          "export",
          [](const PyController& c, const std::string& format, const std::string& out, const std::string& prefix,
             const std::string& encoding) {
            ExportRequest req;
            req.format = format;
            req.out_dir = out;
            req.prefix = prefix;
            req.encoding = encoding;
            const ExportResult r = c.c->export_to(req);
            if (!r.ok) throw py::value_error(r.message);
            py::dict d;
            d["files"] = r.files;
            d["message"] = r.message;
            d["const_data_bytes"] = r.const_data_bytes;
            d["dense_bytes"] = r.dense_bytes;
            d["rle_bytes"] = r.rle_bytes;
            d["encoding"] = r.encoding;
            d["entries"] = r.entries;
            return d;
          },
          py::arg("format"), py::arg("out") = ".", py::arg("prefix") = "", py::arg("encoding") = "auto",
          "As `marsyn export`: format 'c' or 'scs' (docs/deploy.md).")
      .def("__repr__", [](const PyController& c) {
        return "<marsyn.Controller" + (c.agent.empty() ? std::string() : " '" + c.agent + "'") + ": n=" +
               std::to_string(c.c->state_dim()) + ", m=" + std::to_string(c.c->input_dim()) +
               ", horizon=" + std::to_string(c.c->horizon()) + ">";
      });

  m.def(
      "read_controller",
      [](const py::object& path, const py::object& tracker_name) {
        const std::string file = py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
        auto registry = std::make_shared<PluginRegistry>();
        // Without a name, every installed tracker is asked in turn: each recognises its own files
        // (their first bytes), so the caller need not know which tracker wrote one.
        const std::vector<std::string> names =
            tracker_name.is_none() ? registry->names("tracker") : std::vector<std::string>{tracker_name.cast<std::string>()};
        std::string errors;
        for (const auto& name : names) {
          auto tracker = registry->create<Tracker>(name);
          PyController pc;
          try {
            pc.c = tracker->read_controller(file);
          } catch (const std::exception& e) {
            errors += (errors.empty() ? "" : "; ") + (names.size() > 1 ? name + ": " : std::string()) + e.what();
            continue;
          }
          pc.keep = tracker;
          pc.agent = fs::path(file).stem().string();
          return pc;
        }
        throw ConfigError(file, 0, 0, "", names.empty() ? std::string("no tracker plugin is installed") : errors);
      },
      py::arg("path"), py::arg("tracker") = py::none(),
      "Read a controller file written by a tracker plugin (by default the installed tracker that recognises it); "
      "a corrupt file raises ConfigError.");
}

#ifdef MARSYN_HAVE_PLANNING
// plan() and track(): stages 1-3 through the Setup, as `marsyn plan` and `marsyn track`.
void bind_plan_and_track(py::module_& m) {
  m.def(
      "plan",
      [](const PyProblem& p, py::object log) {
        Setup setup(p.lp);
        const Problem& pb = setup.problem();
        planning::PlanSearchOptions po;
        po.log = progress(log);
        po.progress = [p = std::make_shared<planning::SolverProgress>(po.log, planning::SolverProgress::Sink{})](
                          const PlanProgress& x) { (*p)(x); };
        planning::PlanOutcome out;
        {
          py::gil_scoped_release release;
          out = setup.plan(po);
          po.log = nullptr;
          po.progress = nullptr;
        }
        py::dict d;
        d["feasible"] = out.feasible;
        d["horizon"] = out.horizon;
        d["status"] = to_string(out.result.status);
        d["message"] = out.result.message;
        d["min_margin"] = out.check.min_margin;
        d["worst"] = out.check.worst;
        d["time_s"] = out.total_time_s;
        d["iterations"] = out.result.iterations;
        d["x"] = matrix(out.plan.x, out.plan.x.empty() ? 0 : static_cast<int>(out.plan.x.front().size()));
        d["u"] = matrix(out.plan.u, out.plan.u.empty() ? 0 : static_cast<int>(out.plan.u.front().size()));
        d["agents"] = nominal_dict(pb, out.nominal);
        d["summary"] = planning::summary(pb, out);
        return d;
      },
      py::arg("problem"), py::arg("log") = py::none(),
      "The eps-robust plan, as `marsyn plan`: dict with feasible, horizon, status, min_margin, time_s, x (T+1, N), "
      "u (T, M), agents {name: {x, u}}. Progress lines go to `log` (a callable) or the 'marsyn' logger.");

  m.def(
      "track",
      [](const PyProblem& p, const std::string& agent, py::object plan, int threads, py::object log) {
        Setup setup(p.lp);
        const Problem& pb = setup.problem();
        int index = -1;
        for (size_t i = 0; i < pb.agents.size(); ++i)
          if (pb.agents[i].name == agent) index = static_cast<int>(i);
        if (index < 0) throw ConfigError(pb.source, 0, 0, "agent", "no agent named '" + agent + "'");
        std::vector<NominalTrajectory> nominal;
        if (plan.is_none()) {
          planning::PlanSearchOptions po;
          po.log = progress(log);
          po.progress = [p = std::make_shared<planning::SolverProgress>(po.log, planning::SolverProgress::Sink{})](
                            const PlanProgress& x) { (*p)(x); };
          py::gil_scoped_release release;
          nominal = setup.nominal(po);
          po.log = nullptr;
          po.progress = nullptr;
        } else {
          nominal = nominal_from(pb, plan);
        }
        TrackOptions to;  // its memory budget: the loaded problem's, set by the Setup
        to.threads = threads;
        FallbackTrack tracked;
        {
          const auto log_line = progress(log);
          py::gil_scoped_release release;
          tracked = setup.track(index, nominal[static_cast<size_t>(index)], to, log_line);
        }
        const TrackResult& r = tracked.result;
        py::dict d;
        d["agent"] = agent;
        d["tracker"] = tracked.tracker;
        d["automatic"] = tracked.automatic;
        d["tried"] = tracked.tried;
        d["status"] = to_string(r.status);
        d["message"] = r.message;
        d["stats"] = stats_dict(r.stats);
        if (r.controller) d["controller"] = PyController{r.controller, tracked.instance, agent};
        else d["controller"] = py::none();
        d["nominal"] = nominal_dict(pb, nominal)[py::str(agent)];
        return d;
      },
      py::arg("problem"), py::arg("agent"), py::arg("plan") = py::none(), py::arg("threads") = 2,
      py::arg("log") = py::none(),
      "One agent's controller, as `marsyn track`: the agent's tracker and, under `tracker: auto`, on 'no controller' "
      "the next tracker that accepted the agent. plan is a dict from plan()/solve(), a plan.json path, or None (plan "
      "now). Returns {agent, tracker (the one whose result this is), automatic, tried, status, message, stats, "
      "controller, nominal}.");
}
#endif

#ifdef MARSYN_HAVE_PLANNING
// solve(): everything through the Setup, as `marsyn solve`.
void bind_solve(py::module_& m) {
  m.def(
      "solve",
      [](const PyProblem& p, int runs, int threads, double global_budget, py::object out, py::object log,
         std::optional<double> time_limit) {
        // The search's budget as `marsyn solve` takes it: the argument over the file's search.time_limit.
        SolveOptions so = solve_options_for(*p.lp);
        if (time_limit) {
          if (!(*time_limit > 0) || !std::isfinite(*time_limit))
            throw py::value_error("time_limit: expected a positive number of seconds, got " + std::to_string(*time_limit));
          so.time_limit_s = *time_limit;
        }
        so.verification_runs = runs;
        so.threads = threads;
        so.global_memory_budget_bytes = global_budget;
        so.log = progress(log);
        SolveOutcome outcome;
        std::string dir;
        if (!out.is_none()) {  // the folder before the work: a bad `out` fails now, not after the solve
          dir = py::str(py::module_::import("os").attr("fspath")(out)).cast<std::string>();
          (void)OutputFolder(dir);
        }
        {
          py::gil_scoped_release release;
          outcome = Setup(p.lp).solve(so);
          so.log = nullptr;
        }
        py::list files;
        if (!out.is_none())
          for (const auto& f : write_solve_outputs(dir, outcome)) files.append(f);
        py::dict d = json_to_python(result_json(outcome)).cast<py::dict>();
        d["verified"] = outcome.verified;
        d["files"] = files;
        d["nominal"] = nominal_dict(outcome.problem, outcome.plan.nominal);
        py::dict ctrls;
        for (const auto& a : outcome.agents)
          if (a.track.controller) ctrls[py::str(a.name)] = PyController{a.track.controller, p.lp, a.name};
        d["controllers"] = ctrls;
        d["tubes"] = python::tubes(outcome);
        d["margins"] = python::margins(outcome);
        d["changes"] = python::search_changes(p.lp->problem, outcome);
        return d;
      },
      py::arg("problem"), py::arg("runs") = 0, py::arg("threads") = 2, py::arg("global_budget") = 2e9,
      py::arg("out") = py::none(), py::arg("log") = py::none(), py::arg("time_limit") = py::none(),
      "Everything, as `marsyn solve` (time_limit: the search's budget in seconds, as --time-limit; default the file's "
      "search.time_limit): the result.json fields as a dict, plus verified, nominal {name: {x, u}} (numpy), "
      "controllers {name: Controller}, tubes {name: {t, nominal, lo, hi, eps, enclosures}}, margins (one dict per kept "
      "closed-loop run: t, samples, dense_t, dense), changes (what the search changed against the file: {agent, what, "
      "given, used}) and, with out=DIR, the files written there.");
}
#endif

// simulate(), as `marsyn simulate`.
void bind_simulate(py::module_& m) {
  m.def(
      "simulate",
      [](const PyProblem& p, py::object controllers, py::object plan, const std::string& disturbance, std::uint64_t seed,
         int substeps) {
        const Problem& pb = p.lp->problem;
        DisturbanceMode mode;
        try {
          mode = parse_disturbance_mode(disturbance);
        } catch (const std::invalid_argument& e) {
          throw py::value_error(e.what());
        }
        std::vector<std::shared_ptr<const void>> keep;
        std::vector<std::shared_ptr<const Controller>> ctrls;
        if (!controllers.is_none()) ctrls = controllers_from(pb, controllers, keep, p.lp);
        if (plan.is_none()) {
          if (!(py::isinstance<py::str>(controllers) || py::hasattr(controllers, "__fspath__")))
            throw py::value_error("plan: required unless controllers is a solve folder (its plan.json)");
          plan = py::module_::import("os").attr("path").attr("join")(controllers, "plan.json");
        }
        SimulationSetup setup{&pb, nominal_from(pb, plan), ctrls, substeps};
        ClosedLoopRun run;
        SpecEvaluation ev;
        {
          py::gil_scoped_release release;
          run = simulate(setup, {mode, seed, 0});
          ev = SpecMonitor(pb).evaluate(run.states);
        }
        py::dict d;
        const int width = run.states.empty() ? 0 : static_cast<int>(run.states.front().size());
        d["states"] = matrix(run.states, width);
        py::dict per_agent;
        const ProductLayout layout(pb);
        for (std::size_t i = 0; i < pb.agents.size(); ++i) {
          const AgentSpec& a = pb.agents[i];
          std::vector<Eigen::VectorXd> xs;
          for (const auto& s : run.states) xs.push_back(s.segment(layout.state[i], a.n()));
          per_agent[py::str(a.name)] = matrix(xs, a.n());
        }
        d["agents"] = per_agent;
        d["disturbance"] = to_string(mode);
        d["closed_loop"] = !ctrls.empty();
        d["satisfied"] = ev.satisfied;
        d["min_margin"] = ev.min_margin;
        d["worst"] = ev.worst;
        d["max_tube_excess"] = run.max_tube_excess;
        d["outside_domain_agent"] =
            run.outside_domain_agent >= 0 ? py::object(py::str(pb.agents[static_cast<size_t>(run.outside_domain_agent)].name)) : py::none();
        d["outside_domain_step"] = run.outside_domain_step;
        return d;
      },
      py::arg("problem"), py::arg("controllers"), py::arg("plan") = py::none(), py::arg("disturbance") = "uniform",
      py::arg("seed") = 1, py::arg("substeps") = 20,
      "All agents' closed loop (or open loop with controllers=None) under a disturbance mode (none, vertex, paper, "
      "uniform, switching), as `marsyn simulate`. controllers: {name: Controller}, a list, or a solve folder. Returns "
      "states (T+1, N), agents {name: (T+1, n)}, satisfied, min_margin, worst, max_tube_excess, outside_domain_*.");
}

}  // namespace

PYBIND11_MODULE(marsyn, m) {
  m.doc() = "marsyn: formally guaranteed, decentralized controllers for multi-agent reach-avoid problems (docs/python.md)";
  add_module_plugin_paths();
  m.attr("OK") = 0;
  m.attr("OUTSIDE_DOMAIN") = 1;
  m.attr("OUTSIDE_HORIZON") = 2;
#ifdef MARSYN_VERSION
  m.attr("__version__") = MARSYN_VERSION;
#endif

  bind_errors(m);
  bind_problem(m);
  bind_controller(m);
#ifdef MARSYN_HAVE_PLANNING
  bind_plan_and_track(m);
  bind_solve(m);
#endif
  bind_simulate(m);
}
