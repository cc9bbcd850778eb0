#include "marsyn/core/tracking/rank_fanout.hpp"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "marsyn/core/tracking/track_agents.hpp"
#include "marsyn/core/tracking/tracker_choice.hpp"
#include "../mpi/bytes.hpp"
#include "marsyn/core/tracking/sweep_progress.hpp"
#include "marsyn/stopwatch.hpp"
#include "marsyn/number_text.hpp"

namespace fs = std::filesystem;

namespace marsyn {
namespace {

// A figure: name, label, which alternative, its value.
void put_figure(mpi::ByteWriter& w, const TrackerFigure& f) {
  w.put(f.name);
  w.put(f.label);
  w.put(static_cast<std::int32_t>(f.value.index()));
  std::visit([&](const auto& v) { w.put(v); }, f.value);
}
template <std::size_t I>
void get_alternative(mpi::ByteReader& r, std::size_t index, TrackerFigure::Value& value) {
  if constexpr (I < std::variant_size_v<TrackerFigure::Value>) {
    if (index != I) return get_alternative<I + 1>(r, index, value);
    std::variant_alternative_t<I, TrackerFigure::Value> v{};
    r.get(v);
    value = std::move(v);
  } else {
    throw std::runtime_error("a tracker figure of an unknown kind crossed the ranks");
  }
}
void get_figure(mpi::ByteReader& r, TrackerFigure& f) {
  r.get(f.name);
  r.get(f.label);
  std::int32_t index = 0;
  r.get(index);
  get_alternative<0>(r, static_cast<std::size_t>(index), f.value);
}

void put_stats(mpi::ByteWriter& w, const TrackerStats& s) {
  w.put(s.state_input_pairs);
  w.put(s.boxes_computed);
  w.put(s.abstraction_time_s);
  w.put(s.synthesis_time_s);
  w.put(s.peak_memory_bytes);
  w.put(s.enclosure_time_s);
  w.put(s.enclosure_substeps);
  w.put(static_cast<std::int64_t>(s.figures.size()));
  for (const auto& f : s.figures) put_figure(w, f);
  w.put(s.tube_kept);
}
void get_stats(mpi::ByteReader& r, TrackerStats& s) {
  r.get(s.state_input_pairs);
  r.get(s.boxes_computed);
  r.get(s.abstraction_time_s);
  r.get(s.synthesis_time_s);
  r.get(s.peak_memory_bytes);
  r.get(s.enclosure_time_s);
  r.get(s.enclosure_substeps);
  std::int64_t count = 0;
  r.get(count);
  s.figures.resize(static_cast<std::size_t>(count));
  for (auto& f : s.figures) get_figure(r, f);
  r.get(s.tube_kept);
}

// Every rank runs the search in lock step and picks its levers from the failures: the owner's
// reason must reach every rank, or the ranks choose different rounds. One list of the fields for
// both directions.
template <class Failure, class Io>
void failure_fields(Failure& f, Io&& io) {
  io(f.kind);
  io(f.coordinate);
  io(f.step);
  io(f.amount);
  io(f.input_saturation);
  io(f.off_centre);
  io(f.tube_use);
}

// A controller crosses ranks as the bytes of its file (the one format every tracker already
// writes and reads back), through a private file in the temporary directory ($TMPDIR).
fs::path scratch_path(int rank, const std::string& agent) {
  return fs::temp_directory_path() /
         ("marsyn-rank" + std::to_string(rank) + "-" + std::to_string(::getpid()) + "-" + agent + ".ctrl");
}

std::vector<std::uint8_t> controller_bytes(const Controller& c, int rank, const std::string& agent) {
  fs::path p;
  try {
    p = scratch_path(rank, agent);
    c.write(p.string());
  } catch (const std::exception& e) {
    std::error_code ec;
    fs::remove(p, ec);
    throw std::runtime_error("rank " + std::to_string(rank) + ": cannot pass the controller of " + agent +
                             " to rank 0: " + e.what());
  }
  std::ifstream in(p, std::ios::binary);
  std::vector<std::uint8_t> b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const bool ok = !in.bad();
  std::error_code ec;
  fs::remove(p, ec);
  if (!ok) throw std::runtime_error("rank " + std::to_string(rank) + ": cannot read back " + p.string());
  return b;
}

std::shared_ptr<const Controller> controller_from(const Tracker& t, const std::vector<std::uint8_t>& b, int rank,
                                                  const std::string& agent) {
  const fs::path p = scratch_path(rank, agent);
  {
    std::ofstream out(p, std::ios::binary);
    out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    if (!out) throw std::runtime_error("rank " + std::to_string(rank) + ": cannot write " + p.string());
  }
  try {
    auto c = t.read_controller(p.string());
    fs::remove(p);
    return c;
  } catch (...) {
    std::error_code ec;
    fs::remove(p, ec);
    throw;
  }
}

std::string result_line(const AgentOutcome& o, const std::string& where, double seconds) {
  std::ostringstream s;
  s.precision(kMessageDigits);
  s << "[track] " << o.name << " (" << o.tracker << ", " << where << "): " << to_string(o.track.status) << ", "
    << stats_text(o.track.stats) << ", " << seconds << " s";
  if (!o.track.message.empty()) s << " (" << o.track.message << ")";
  return s.str();
}

}  // namespace

RankAssignment assign_agents_to_ranks(const std::vector<double>& work, int ranks) {
  const int N = static_cast<int>(work.size());
  RankAssignment a;
  a.rank_of.assign(static_cast<size_t>(N), 0);
  std::vector<int> order(static_cast<size_t>(N));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return work[x] > work[y]; });
  const double total = std::accumulate(work.begin(), work.end(), 0.0);
  std::vector<double> load(static_cast<size_t>(std::max(1, ranks)), 0.0);
  for (int i : order) {
    if (ranks > 1 && total > 0 && work[i] > total / ranks) {
      a.split.push_back(i);
      a.rank_of[i] = -1;
      continue;
    }
    // Largest first onto the least loaded rank (lowest rank on ties); an agent without an
    // estimate counts as a small one, so that such agents still spread.
    const int r = static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
    a.rank_of[i] = r;
    load[static_cast<size_t>(r)] += std::max(work[i], 1e-9);
  }
  return a;
}

std::vector<AgentOutcome> track_agents_over_ranks(const Problem& pb, const std::vector<NominalTrajectory>& nominal,
                                                  const std::vector<std::shared_ptr<const Tracker>>& trackers,
                                                  const SolveOptions& opt, const MemoryBudget& budget,
                                                  const Collective& world) {
  const int N = static_cast<int>(pb.agents.size()), R = world.size(), me = world.rank();
  auto log = [&](const std::string& s) {
    if (opt.log) opt.log(s);
  };
  std::vector<double> work(static_cast<size_t>(N), 0.0);
  for (int i = 0; i < N; ++i)
    work[i] = std::max(0.0, assess_tracker(*trackers[i], pb.agents[i], {static_cast<int>(nominal[i].x.size()) - 1, pb.tau, budget}).work_s);
  const RankAssignment as = assign_agents_to_ranks(work, R);
  {
    std::string where;
    for (int i = 0; i < N; ++i)
      where += (i ? ", " : "") + pb.agents[i].name + (as.rank_of[i] < 0 ? " on all ranks" : " on rank " + std::to_string(as.rank_of[i]));
    log("[track] " + std::to_string(N) + " agents over " + std::to_string(R) + " ranks: " + where);
  }
  std::vector<AgentOutcome> out(static_cast<size_t>(N));

  // 1. The heavy agents, one after the other, each over every rank. An exception here ends the
  // run (the CLI aborts every rank): the other ranks would wait for this one forever.
  for (int i : as.split) {
    const Stopwatch t0;
    TrackOptions topt;
    topt.threads = opt.threads;
    topt.memory_budget_bytes = budget.bytes;
    topt.collective = &world;
    if (opt.log || opt.live) {
      auto p = std::make_shared<SweepProgress>(pb.agents[i].name + " (all " + std::to_string(R) + " ranks)", opt.log, opt.live);
      topt.progress = [p](int done, int total) { (*p)(done, total); };
    }
    AgentOutcome& o = out[static_cast<size_t>(i)];
    o.name = pb.agents[i].name;
    o.tracker = pb.agents[i].tracker.name;
    o.track = trackers[i]->track(tracking_problem(pb, i, nominal[i]), topt);
    log(result_line(o, "all ranks", t0.seconds()));
  }

  // 2. This rank's own agents, side by side on its threads (the single-process fan-out).
  std::vector<int> mine;
  for (int i = 0; i < N; ++i)
    if (as.rank_of[i] == me) mine.push_back(i);
  if (!mine.empty()) {
    Problem sub = pb;
    sub.agents.clear();
    std::vector<NominalTrajectory> sub_nominal;
    std::vector<std::shared_ptr<const Tracker>> sub_trackers;
    for (int i : mine) {
      sub.agents.push_back(pb.agents[i]);
      sub_nominal.push_back(nominal[i]);
      sub_trackers.push_back(trackers[i]);
    }
    std::vector<AgentOutcome> got = track_agents(sub, sub_nominal, sub_trackers, opt, budget);
    for (std::size_t q = 0; q < mine.size(); ++q) out[static_cast<size_t>(mine[q])] = std::move(got[q]);
  }

  // 3. Every rank's agents to every rank (the next stages need all controllers everywhere).
  bool any_dealt = false;
  for (int i = 0; i < N; ++i) any_dealt = any_dealt || as.rank_of[i] >= 0;
  if (!any_dealt) return out;
  mpi::ByteWriter w;
  for (int i : mine) {
    const AgentOutcome& o = out[static_cast<size_t>(i)];
    w.put<std::int32_t>(i);
    w.put(o.name);
    w.put(o.tracker);
    w.put<std::int32_t>(static_cast<std::int32_t>(o.track.status));
    w.put(o.track.message);
    put_stats(w, o.track.stats);
    failure_fields(o.track.failure, [&](const auto& x) { w.put(x); });
    w.put<std::uint8_t>(o.track.controller ? 1 : 0);
    if (o.track.controller) w.put(controller_bytes(*o.track.controller, me, o.name));
  }
  const auto all = world.allgather(w.bytes());
  for (int q = 0; q < R; ++q) {
    if (q == me) continue;
    mpi::ByteReader r(all[static_cast<size_t>(q)]);
    while (!r.done()) {
      std::int32_t i = -1, status = 0;
      r.get(i);
      if (i < 0 || i >= N || as.rank_of[i] != q) throw std::runtime_error("rank " + std::to_string(q) + " sent an agent it does not own");
      AgentOutcome& o = out[static_cast<size_t>(i)];
      r.get(o.name);
      r.get(o.tracker);
      r.get(status);
      o.track.status = static_cast<TrackerStatus>(status);
      r.get(o.track.message);
      get_stats(r, o.track.stats);
      failure_fields(o.track.failure, [&](auto& x) { r.get(x); });
      std::uint8_t has = 0;
      r.get(has);
      if (has) {
        std::vector<std::uint8_t> b;
        r.get(b);
        o.track.controller = controller_from(*trackers[i], b, me, o.name);
      }
      log(result_line(o, "rank " + std::to_string(q), o.track.stats.abstraction_time_s + o.track.stats.synthesis_time_s +
                                                        o.track.stats.enclosure_time_s));
    }
  }
  return out;
}

}  // namespace marsyn
