#pragma once
// The ranks of one run started by an MPI launcher (`mpirun -np R marsyn solve ...`, `srun
// marsyn solve ...`; docs/mpi.md). The CLI makes one at start-up: MPI is initialised only when
// marsyn was built with it and a launcher started this process, so a plain `marsyn solve` runs
// exactly as without MPI. Core code sees the group as a marsyn::Collective; only this file's
// implementation includes mpi.h.
#include <memory>
#include <string>

#include "marsyn/collective.hpp"

namespace marsyn::mpi {

// True when this marsyn was built with MPI (CMake option MARSYN_WITH_MPI, on when MPI is found).
bool compiled_in();
// "Open MPI v4.1.4, ..." or "not built in", for `marsyn --version`.
std::string description();

class World {
 public:
  // Initialises MPI when compiled in and launched by mpirun/srun; otherwise a world of one.
  World(int& argc, char**& argv);
  ~World();  // finalises MPI
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }
  // The whole group, for the stages that split work; nullptr in a world of one.
  const Collective* collective() const { return size_ > 1 ? collective_.get() : nullptr; }
  // Ends every rank of the run at once (MPI_Abort), after the caller printed why; in a world of
  // one, exits the process.
  [[noreturn]] void abort(int exit_code) const;

 private:
  int rank_ = 0, size_ = 1;
  bool initialised_ = false;
  std::unique_ptr<Collective> collective_;
};

}  // namespace marsyn::mpi
