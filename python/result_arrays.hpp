#pragma once
// The numeric parts of marsyn's results as numpy arrays (docs/python.md): a controller's period
// enclosures and, for solve(), the tubes, the margins of the kept closed-loop runs and what the
// search changed against the problem file.
#include <pybind11/pybind11.h>

#include "marsyn/tracker.hpp"
#ifdef MARSYN_HAVE_PLANNING
#include "marsyn/core/solve.hpp"
#endif

namespace marsyn::python {

namespace py = pybind11;

// {step, t0, t1 (E,), state_lo, state_hi (E, n), workspace_lo, workspace_hi (E, 2)}.
py::dict period_enclosures(const Controller& controller);

#ifdef MARSYN_HAVE_PLANNING
// Per agent: {t (T+1,), nominal, lo, hi (T+1, n): the eps-box tube, eps (n,), enclosures}.
py::dict tubes(const SolveOutcome& outcome);
// One dict per run verify() kept (nominal, paper scenarios, worst run, open loop).
py::list margins(const SolveOutcome& outcome);
// Every parameter the outcome used that differs from the loaded problem's.
py::list search_changes(const Problem& given, const SolveOutcome& outcome);
#endif

}  // namespace marsyn::python
