#include "mpi_runs.hpp"

#include <stdexcept>
#include <string>

#include "../tracking/mpi_bytes.hpp"

namespace marsyn::mpi {

void exchange_runs(const Collective& c, std::vector<RunSummary>& runs) {
  const int n = static_cast<int>(runs.size()), R = c.size(), me = c.rank();
  if (R <= 1) return;
  ByteWriter w;
  for (int r = me; r < n; r += R) {
    const RunSummary& s = runs[static_cast<size_t>(r)];
    w.put<std::int32_t>(static_cast<std::int32_t>(s.scenario.mode));
    w.put(s.scenario.seed);
    w.put(s.scenario.variant);
    w.put(s.satisfied);
    w.put(s.min_margin);
    w.put(s.worst);
    w.put(s.left_tube);
    w.put(s.outside_domain);
    w.put(s.between.obstacle);
    w.put(s.between.collision);
    w.put(s.between.formation);
    w.put(s.sampled_margin);
  }
  const auto all = c.allgather(w.bytes());
  for (int q = 0; q < R; ++q) {
    if (q == me) continue;
    ByteReader rd(all[static_cast<size_t>(q)]);
    for (int r = q; r < n; r += R) {
      RunSummary& s = runs[static_cast<size_t>(r)];
      std::int32_t mode = 0;
      rd.get(mode);
      s.scenario.mode = static_cast<DisturbanceMode>(mode);
      rd.get(s.scenario.seed);
      rd.get(s.scenario.variant);
      rd.get(s.satisfied);
      rd.get(s.min_margin);
      rd.get(s.worst);
      rd.get(s.left_tube);
      rd.get(s.outside_domain);
      rd.get(s.between.obstacle);
      rd.get(s.between.collision);
      rd.get(s.between.formation);
      rd.get(s.sampled_margin);
    }
    if (!rd.done()) throw std::runtime_error("rank " + std::to_string(q) + " sent more verification runs than it owns");
  }
}

}  // namespace marsyn::mpi
