#include <algorithm>

#include "altro_solver.hpp"
#include "marsyn/number_text.hpp"

namespace marsyn::altro {

namespace {
// Per requirement row, once: core's constraint object (sample and between-sample rows), the
// solver's reference with its support map, the broad phase's entry, the held lists (fitted on
// the unicycle field, scripts/unicycle_field.py: peak RSS 559 MB at 400 robots (T = 193) and 2.2 GB
// at 1000 (T = 123) against 541 MB and 2.5 GB from this formula).
constexpr double kBytesPerRow = 1024.0;
// Whatever size the team: the threads' scratch, the exact check's and the outputs' buffers
// (measured: 6 MB at 25 robots, 41 MB at 100, where the terms above give 4 MB and 32 MB).
constexpr double kBaseBytes = 16.0 * 1024 * 1024;
}  // namespace

PlannerMemory memory(const Problem& pb) {
  const double steps = static_cast<double>(pb.horizon) + 1;
  const double N = static_cast<double>(pb.agents.size());
  double blocks = 0;
  for (const auto& a : pb.agents) {
    const double k = a.n() + a.m();
    blocks += 32.0 * k * k;  // Jacobians, gains, cost expansion, iterates and candidates: 4 doubles per entry
  }
  const double pairs = (pb.pairwise_collision ? N * (N - 1) / 2 : 0.0) + static_cast<double>(pb.formation.size());
  const double obstacle_rows = N * static_cast<double>(pb.obstacles.size());
  const double rows = pairs + obstacle_rows;
  const double copies = pb.guarantee == Guarantee::Continuous ? 2.0 : 1.0;  // at the samples, between them
  PlannerMemory m;
  m.bytes = kBaseBytes + steps * (blocks + 8.0 * copies * rows) + kBytesPerRow * copies * rows;
  m.detail = "16 MiB + " + number_text(steps, 3) + " steps x (" + number_text(N, 3) + " agents' blocks + a multiplier per row) + " +
             number_text(pairs, 3) + " pair and " + number_text(obstacle_rows, 3) + " obstacle rows" +
             (copies > 1 ? " (at and between the samples)" : "");
  return m;
}

}  // namespace marsyn::altro
