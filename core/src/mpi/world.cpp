#include "marsyn/core/mpi/world.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <limits>
#include <stdexcept>

#ifdef MARSYN_HAVE_MPI
#include <mpi.h>
#endif

namespace marsyn::mpi {

#ifdef MARSYN_HAVE_MPI
namespace {

// Set by mpirun (Open MPI, MPICH/Hydra) or srun (PMI/PMIx) in every process they start.
bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE", "MPI_LOCALNRANKS"})
    if (std::getenv(v)) return true;
  return false;
}

void check(int rc, const char* what) {
  if (rc != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

// Waits for a non-blocking collective without spinning: a rank waiting for rank 0's plan (or for
// a slower rank's step) would otherwise keep a core busy that rank 0's threads need, on a
// machine with fewer cores than threads. A 0.2 ms nap is nothing against a sweep step.
void wait(MPI_Request& r, const char* what) {
  for (;;) {
    int done = 0;
    check(MPI_Test(&r, &done, MPI_STATUS_IGNORE), what);
    if (done) return;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
}

int to_int(std::size_t n) {
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::runtime_error("MPI: a message of more than 2 GiB");
  return static_cast<int>(n);
}

// MPI_COMM_WORLD as a Collective: called from one thread per rank (MPI_THREAD_FUNNELED).
class MpiCollective final : public Collective {
 public:
  MpiCollective(int rank, int size) : rank_(rank), size_(size) {}
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  std::vector<std::vector<std::uint8_t>> allgather(const std::vector<std::uint8_t>& mine) const override {
    const int n = to_int(mine.size());
    std::vector<int> counts(static_cast<size_t>(size_)), displs(static_cast<size_t>(size_));
    MPI_Request req;
    check(MPI_Iallgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD, &req), "MPI_Iallgather");
    wait(req, "MPI_Iallgather");
    std::size_t total = 0;
    for (int q = 0; q < size_; ++q) {
      displs[static_cast<size_t>(q)] = to_int(total);
      total += static_cast<std::size_t>(counts[static_cast<size_t>(q)]);
    }
    to_int(total);
    std::vector<std::uint8_t> all(total);
    std::uint8_t dummy = 0;
    check(MPI_Iallgatherv(mine.empty() ? &dummy : mine.data(), n, MPI_BYTE, all.empty() ? &dummy : all.data(),
                          counts.data(), displs.data(), MPI_BYTE, MPI_COMM_WORLD, &req),
          "MPI_Iallgatherv");
    wait(req, "MPI_Iallgatherv");
    std::vector<std::vector<std::uint8_t>> out(static_cast<size_t>(size_));
    for (int q = 0; q < size_; ++q) {
      const auto b = all.begin() + displs[static_cast<size_t>(q)];
      out[static_cast<size_t>(q)].assign(b, b + counts[static_cast<size_t>(q)]);
    }
    return out;
  }
  void broadcast(std::vector<std::uint8_t>& bytes, int root) const override {
    unsigned long long n = bytes.size();
    MPI_Request req;
    check(MPI_Ibcast(&n, 1, MPI_UNSIGNED_LONG_LONG, root, MPI_COMM_WORLD, &req), "MPI_Ibcast");
    wait(req, "MPI_Ibcast");
    to_int(n);
    if (rank_ != root) bytes.resize(static_cast<size_t>(n));
    if (n == 0) return;
    check(MPI_Ibcast(bytes.data(), static_cast<int>(n), MPI_BYTE, root, MPI_COMM_WORLD, &req), "MPI_Ibcast");
    wait(req, "MPI_Ibcast");
  }

 private:
  int rank_, size_;
};

}  // namespace

bool compiled_in() { return true; }

std::string description() {
  char v[MPI_MAX_LIBRARY_VERSION_STRING];
  int len = 0;
  MPI_Get_library_version(v, &len);
  std::string s(v, static_cast<size_t>(len));
  if (const auto cut = s.find_first_of(",\n"); cut != std::string::npos) s.resize(cut);
  return "built in (" + s + ")";
}

World::World(int& argc, char**& argv) {
  if (!launched_by_mpi()) return;
  int provided = 0;
  check(MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  initialised_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  collective_ = std::make_unique<MpiCollective>(rank_, size_);
}

World::~World() {
  if (!initialised_) return;
  // Ranks that finish first wait here, napping, for rank 0 to write the output folder.
  MPI_Request req;
  if (MPI_Ibarrier(MPI_COMM_WORLD, &req) == MPI_SUCCESS) {
    try {
      wait(req, "MPI_Ibarrier");
    } catch (...) {
    }
  }
  MPI_Finalize();
}

void World::abort(int exit_code) const {
  std::fflush(stdout);
  std::fflush(stderr);
  if (initialised_) MPI_Abort(MPI_COMM_WORLD, exit_code);
  std::_Exit(exit_code);
}

#else  // built without MPI: always a world of one

bool compiled_in() { return false; }
std::string description() { return "not built in"; }
World::World(int&, char**&) {
  // Started by mpirun although built without MPI: every process would solve alone and write the
  // same folder; say so rather than let it pass unnoticed.
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  if (size && std::atoi(size) > 1 && std::getenv("OMPI_COMM_WORLD_RANK") && std::atoi(std::getenv("OMPI_COMM_WORLD_RANK")) == 0)
    std::fprintf(stderr, "marsyn: warning: started by mpirun with %s processes, but built without MPI "
                         "(docs/mpi.md): each process runs alone\n", size);
}
World::~World() = default;
void World::abort(int exit_code) const {
  std::fflush(stdout);
  std::fflush(stderr);
  std::_Exit(exit_code);
}

#endif

}  // namespace marsyn::mpi
