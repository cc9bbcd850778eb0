#pragma once
// The knobs of one `marsyn solve` run (threads, budgets, the progress sink), shared by the
// orchestrator and the stages it drives.
#include <functional>
#include <string>

#include "marsyn/collective.hpp"

namespace marsyn {

struct SolveOptions {
  int verification_runs = 0;  // 0: default_verification_runs (1000 up to 100 agents)
  int threads = 2;
  // The search's budget (docs/search.md): it goes on while a lever is left and its estimate of
  // the next round fits in what is left of this many seconds.
  double time_limit_s = 600.0;
  // A backstop only: the levers' own caps and "never the same attempt twice" end the search long
  // before (at most about 20 rounds).
  int max_rounds = 100;
  double global_memory_budget_bytes = 2e9;  // the global ABCD baseline is attempted below this
  std::function<void(const std::string&)> log;  // progress lines; may be empty
  // A transient status line (a progress bar on a terminal), drawn over the previous one; an
  // empty line clears it. May be empty: progress then goes to `log` as plain lines.
  std::function<void(const std::string&)> live;
  // The ranks of an MPI run (docs/mpi.md); nullptr: this process alone. Every rank calls
  // solve() with the same problem; rank 0 plans and reports.
  const Collective* cluster = nullptr;
  // True once the run should end (SIGINT or SIGTERM: apps/marsyn installs the handler); may be
  // empty. The search then stops between agents, horizons and rounds, and solve() returns what
  // it has (status stopped). The search adds its own time limit to it.
  std::function<bool()> stop;
  // `marsyn solve --resume DIR`: a folder an earlier solve of this problem left (stopped or
  // failed): its plan is kept when it is still eps-robust with the tubes result.json records, and
  // so are the controllers found for it; the search tracks only the other agents.
  std::string resume_dir;
};

struct LoadedProblem;

// What every front end (the CLI's solve and bench, Python) starts from: the defaults, with what
// the problem file asks of the run (search.time_limit) applied; a command line's own values then
// go over it.
SolveOptions solve_options_for(const LoadedProblem& loaded);

}  // namespace marsyn
