#pragma once
// The closed-loop verification runs of an MPI run (docs/mpi.md): run r belongs to rank
// r mod size; after its runs, every rank sends their summaries to every rank, so each one reduces
// the same complete list in the same order as one process would.
#include <vector>

#include "marsyn/collective.hpp"
#include "marsyn/core/verification/verification.hpp"

namespace marsyn::mpi {

inline bool owns_run(const Collective* c, int run) { return !c || c->size() <= 1 || run % c->size() == c->rank(); }

// Fills every entry of `runs` this rank does not own from its owner.
void exchange_runs(const Collective& c, std::vector<RunSummary>& runs);

}  // namespace marsyn::mpi
