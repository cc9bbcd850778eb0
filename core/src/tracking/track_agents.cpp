#include "marsyn/core/tracking/track_agents.hpp"

#include "marsyn/core/tracking/rank_fanout.hpp"
#include "marsyn/core/tracking/sweep_progress.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <sstream>
#include <thread>

#include "marsyn/core/parallel_tasks.hpp"
#include "marsyn/core/tracking/tracker_choice.hpp"
#include "marsyn/stopwatch.hpp"
#include "marsyn/number_text.hpp"

namespace marsyn {

TrackingProblem tracking_problem(const Problem& pb, int index, const NominalTrajectory& nominal) {
  const AgentSpec& a = pb.agents[index];
  TrackingProblem tp;
  tp.agent = a.name;
  tp.dynamics = a.dynamics;
  tp.nominal = nominal;
  tp.tube = a.tube;
  tp.fields = a.fields;
  tp.input_bounds = a.input_bounds;
  tp.state_bounds = a.state_bounds;
  tp.tau = pb.tau;
  tp.workspace = a.workspace;
  tp.initial_radius = a.x0_radius;
  return tp;
}

std::vector<AgentOutcome> track_agents(const Problem& pb, const std::vector<NominalTrajectory>& nominal,
                                       const std::vector<std::shared_ptr<const Tracker>>& trackers,
                                       const SolveOptions& opt, const MemoryBudget& budget) {
  if (opt.cluster && opt.cluster->size() > 1) {
    SolveOptions here = opt;
    here.cluster = nullptr;  // each rank's own agents: this function, on its threads
    return track_agents_over_ranks(pb, nominal, trackers, here, budget, *opt.cluster);
  }
  const int N = static_cast<int>(pb.agents.size());
  std::vector<AgentOutcome> out(N);
  // Agents in parallel, one tracker thread each, when the work is spread over them; when one
  // agent dominates (the crane beside a vehicle: 4 vs 2 dimensions), agents run one after the
  // other with all threads each. Work estimate: each agent's tracker's own (assess().work_s).
  std::vector<double> work_estimate(N, 0.0);
  double total_work = 0, max_work = 0;
  for (int i = 0; i < N; ++i) {
    const double w =
        std::max(0.0, assess_tracker(*trackers[i], pb.agents[i], {static_cast<int>(nominal[i].x.size()) - 1, pb.tau, budget}).work_s);
    work_estimate[i] = w;
    total_work += w;
    max_work = std::max(max_work, w);
  }
  const bool dominated = N < opt.threads || max_work > 0.5 * total_work;
  const int workers = dominated ? 1 : std::max(1, std::min(opt.threads, N));
  TrackOptions topt;
  topt.threads = dominated ? opt.threads : 1;
  topt.memory_budget_bytes = budget.bytes;
  topt.stop = opt.stop;  // the time limit and signals end a long synthesis too, not only between agents
  std::atomic<int> done{0};
  std::mutex log_mutex;
  std::vector<char> running(N, 0);
  auto track_one = [&](int i) {
    {
      std::lock_guard<std::mutex> lock(log_mutex);
      running[i] = 1;
    }
    const AgentSpec& a = pb.agents[i];
    const Stopwatch t0;
    out[i].name = a.name;
    out[i].tracker = a.tracker.name;
    if (opt.stop && opt.stop()) {
      // Stopped (a signal, the time limit): the agents not started are not tracked.
      out[i].track.status = TrackerStatus::NoController;
      out[i].track.message = "not tracked: the run was stopped";
      ++done;
      std::lock_guard<std::mutex> lock(log_mutex);
      running[i] = 0;
      return;
    }
    const TrackingProblem tp = tracking_problem(pb, i, nominal[i]);
    try {
      TrackOptions o = topt;
      // One agent at a time with all threads: its sweep step by step (sweep_progress.hpp).
      if (dominated && (opt.log || opt.live)) {
        auto p = std::make_shared<SweepProgress>(a.name, opt.log, opt.live);
        o.progress = [p](int done, int total) { (*p)(done, total); };
      }
      out[i].track = trackers[i]->track(tp, o);
    } catch (const std::exception& e) {
      out[i].track.status = TrackerStatus::InvalidInput;
      out[i].track.message = e.what();
    }
    const int d = ++done;
    if (opt.log) {
      std::lock_guard<std::mutex> lock(log_mutex);
      running[i] = 0;
      std::ostringstream s;
      s.precision(kMessageDigits);
      s << "[track " << d << "/" << N << "] " << a.name << " (" << a.tracker.name
        << "): " << to_string(out[i].track.status) << ", " << stats_text(out[i].track.stats) << ", " << t0.seconds()
        << " s";
      if (!out[i].track.message.empty()) s << " (" << out[i].track.message << ")";
      opt.log(s.str());
    }
  };
  // A heartbeat, so that a long abstraction (minutes for a 4-dimensional agent) is visibly alive.
  std::mutex beat_mutex;
  std::condition_variable beat_cv;
  bool finished = false;
  std::thread heartbeat([&] {
    const Stopwatch t0;
    std::unique_lock<std::mutex> lock(beat_mutex);
    while (!beat_cv.wait_for(lock, std::chrono::seconds(15), [&] { return finished; })) {
      if (!opt.log) continue;
      std::lock_guard<std::mutex> log_lock(log_mutex);
      std::string names;
      for (int i = 0; i < N; ++i)
        if (running[i]) names += (names.empty() ? "" : ", ") + pb.agents[i].name;
      std::ostringstream s;
      s.precision(kMessageDigits);
      s << "[track] " << done.load() << "/" << N << " agents done after " << static_cast<int>(t0.seconds())
        << " s; still working on " << (names.empty() ? "-" : names);
      opt.log(s.str());
    }
  });
  auto stop_heartbeat = [&] {
    {
      std::lock_guard<std::mutex> lock(beat_mutex);
      finished = true;
    }
    beat_cv.notify_all();
    heartbeat.join();
  };
  try {
    parallel_tasks(N, workers, track_one);
  } catch (...) {
    stop_heartbeat();  // a joinable thread left behind would end the program
    throw;
  }
  stop_heartbeat();
  return out;
}

std::string stats_text(const TrackerStats& stats) {
  std::ostringstream s;
  s.precision(kMessageDigits);
  // Counts only: a flag or a per-step list says nothing in one line.
  for (const auto& f : stats.figures) {
    if (const auto* v = std::get_if<long long>(&f.value)) s << *v << " " << f.label << ", ";
    if (const auto* v = std::get_if<double>(&f.value)) s << *v << " " << f.label << ", ";
  }
  if (stats.state_input_pairs > 0) s << "N_l " << stats.state_input_pairs << ", ";
  s << stats.boxes_computed << " boxes";
  return s.str();
}

}  // namespace marsyn
