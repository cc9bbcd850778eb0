// Prints the tracker's figures per scenario (docs/benchmarks-tracker.md records them).
// Usage: marsyn_track_bench [drone|crane|lane|formation|vehicle|pendulum ...] [--threads N] [--out DIR]
//        [--substeps N] [--no-prefilter] [--steps N]
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "abcd_tracker.hpp"
#include "marsyn/stopwatch.hpp"
#include "track_scenarios.hpp"
#include "synthesis.hpp"

using namespace marsyn;
using Steps = std::vector<long long>;  // a figure counted per step (TrackerStats::figures)

int main(int argc, char** argv) {
  std::vector<std::string> which;
  int threads = 2;
  std::string out = "/tmp";
  Params params;
  int steps = 0;  // 0: the scenario's own
  for (int a = 1; a < argc; ++a) {
    if (!std::strcmp(argv[a], "--threads") && a + 1 < argc) threads = std::atoi(argv[++a]);
    else if (!std::strcmp(argv[a], "--out") && a + 1 < argc) out = argv[++a];
    else if (!std::strcmp(argv[a], "--substeps") && a + 1 < argc) params.set("substeps", std::atol(argv[++a]));
    else if (!std::strcmp(argv[a], "--no-prefilter")) params.set("prefilter", false);
    else if (!std::strcmp(argv[a], "--steps") && a + 1 < argc) steps = std::atoi(argv[++a]);
    else which.push_back(argv[a]);
  }
  if (which.empty()) which = {"drone", "crane"};
  abcd::AbcdTracker tracker(params);
  for (const auto& name : which) {
    const Stopwatch clock;
    TrackingProblem p;
    if (name == "drone") p = abcd::scenarios::drone(steps > 0 ? steps : 103);
    else if (name == "crane") p = abcd::scenarios::crane(steps > 0 ? steps : 70);
    else if (name == "lane") p = abcd::scenarios::lane_merging();
    else if (name == "formation") p = abcd::scenarios::formation();
    else if (name == "vehicle") p = abcd::scenarios::vehicle();
    else if (name == "pendulum") p = abcd::scenarios::pendulum();
    else {
      std::fprintf(stderr, "unknown scenario %s\n", name.c_str());
      return 2;
    }
    TrackOptions o;
    o.threads = threads;
    const TrackResult r = tracker.track(p, o);
    const std::string file = out + "/" + name + ".ctl";
    if (r.controller) r.controller->write(file);
    const double wall = clock.seconds();
    const auto& s = r.stats;
    const Steps winning = s.get<Steps>("winning_cells_per_step");
    const long long win0 = winning.empty() ? 0 : winning[0];
    std::printf(
        "%-10s status=%s steps=%zu tube_cells=%lld N_l=%.3g boxes_computed=%lld abstraction_s=%.3f "
        "synthesis_s=%.3f wall_s=%.3f peak_rss_MB=%.1f win0=%lld initial_state_winning=%d threads=%d\n",
        name.c_str(), to_string(r.status), p.nominal.x.size() - 1, s.get<long long>("tube_cells"), s.state_input_pairs, s.boxes_computed,
        s.abstraction_time_s, s.synthesis_time_s, wall, abcd::peak_rss_bytes() / 1048576.0, win0,
        s.get<bool>("initial_state_winning") ? 1 : 0, threads);
    if (r.status != TrackerStatus::ControllerFound) std::printf("  %s\n", r.message.c_str());
    std::printf("  nominal x_0 = (");
    for (int i = 0; i < p.nominal.x.front().size(); ++i) std::printf("%s%.3f", i ? ", " : "", p.nominal.x.front()[i]);
    std::printf("), x_T = (");
    for (int i = 0; i < p.nominal.x.back().size(); ++i) std::printf("%s%.3f", i ? ", " : "", p.nominal.x.back()[i]);
    std::printf(")\n");
  }
  return 0;
}
