#include "marsyn/core/mpi/plan_broadcast.hpp"

#include "bytes.hpp"

namespace marsyn::mpi {

void broadcast_plan(const Collective& c, planning::PlanOutcome& plan) {
  if (c.size() <= 1) return;
  ByteWriter w;
  if (c.rank() == 0) {
    w.put(plan.feasible);
    w.put(plan.horizon);
    w.put(plan.check.message);
    w.put(plan.check.min_margin);
    w.put(plan.total_time_s);
    w.put<std::uint64_t>(plan.nominal.size());
    for (const auto& a : plan.nominal) {
      w.put(a.agent);
      w.put(a.x);
      w.put(a.u);
    }
    w.put<std::uint64_t>(plan.extra.size());
    for (const auto& [name, v] : plan.extra) {
      w.put(name);
      w.put(v);
    }
    w.put(plan.horizon_blocked);
  }
  c.broadcast(w.bytes(), 0);
  if (c.rank() == 0) return;
  ByteReader r(w.bytes());
  plan = {};
  r.get(plan.feasible);
  r.get(plan.horizon);
  r.get(plan.check.message);
  r.get(plan.check.min_margin);
  r.get(plan.total_time_s);
  std::uint64_t n = 0;
  r.get(n);
  plan.nominal.resize(n);
  for (auto& a : plan.nominal) {
    r.get(a.agent);
    r.get(a.x);
    r.get(a.u);
  }
  r.get(n);
  for (std::uint64_t k = 0; k < n; ++k) {
    std::string name;
    double v = 0;
    r.get(name);
    r.get(v);
    plan.extra[name] = v;
  }
  r.get(plan.horizon_blocked);
}

}  // namespace marsyn::mpi
