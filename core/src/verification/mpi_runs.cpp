#include "mpi_runs.hpp"

#include <stdexcept>
#include <string>

#include "../mpi/bytes.hpp"

namespace marsyn::mpi {

namespace {

// The fields of a run, listed once for both directions so that the sender and the receivers
// cannot drift apart: Io is Put (s const) or Get.
template <class Io, class Summary>
void fields(Io& io, Summary& s) {
  io.mode(s.scenario.mode);
  io(s.scenario.seed);
  io(s.scenario.variant);
  io(s.satisfied);
  io(s.min_margin);
  io(s.worst);
  io(s.left_tube);
  io(s.outside_domain);
  io(s.between.obstacle);
  io(s.between.collision);
  io(s.between.formation);
  io(s.sampled_margin);
}

struct Put {
  ByteWriter& w;
  template <class T>
  void operator()(const T& v) { w.put(v); }
  void mode(DisturbanceMode m) { w.put<std::int32_t>(static_cast<std::int32_t>(m)); }
};

struct Get {
  ByteReader& r;
  template <class T>
  void operator()(T& v) { r.get(v); }
  void mode(DisturbanceMode& m) {
    std::int32_t v = 0;
    r.get(v);
    m = static_cast<DisturbanceMode>(v);
  }
};

}  // namespace

void exchange_runs(const Collective& c, std::vector<RunSummary>& runs) {
  const int n = static_cast<int>(runs.size()), R = c.size(), me = c.rank();
  if (R <= 1) return;
  ByteWriter w;
  Put put{w};
  for (int r = me; r < n; r += R) fields(put, runs[static_cast<size_t>(r)]);
  const auto all = c.allgather(w.bytes());
  for (int q = 0; q < R; ++q) {
    if (q == me) continue;
    ByteReader rd(all[static_cast<size_t>(q)]);
    Get get{rd};
    for (int r = q; r < n; r += R) fields(get, runs[static_cast<size_t>(r)]);
    if (!rd.done()) throw std::runtime_error("rank " + std::to_string(q) + " sent more verification runs than it owns");
  }
}

}  // namespace marsyn::mpi
