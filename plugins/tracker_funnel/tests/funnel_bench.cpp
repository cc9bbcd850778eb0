// Benchmark of the funnel tracker's enclosures (docs/funnel.md): every test
// scenario over its full horizon, with the mean-value and the second-order enclosure in the same
// run: how many steps verify, the track time, how much of eps the verified sets fill, and the
// tightness figure (verified half-width / largest deviation in sampled adversarial runs).
//   funnel_bench [name=value...] [scenario...]   (default: every scenario; name=value sets a
//   tracker parameter for both runs, e.g. set_order=4; integers, reals, true/false, words;
//   enclosure=second_order runs that enclosure only; w_scale=x multiplies the disturbance bound;
//   remainder_scale=x scales the Lagrange remainder: UNSOUND below 1, a diagnostic of how much of
//   a miss the remainder makes, hence how much splitting could win at most)
// unicycle_at_bound, unicycle_near_bound: nominals whose speed sits at or near U's bound
// (funnel_scenarios.hpp; docs/funnel.md, "Input-aware weights"), run only when named.
// quadrotor_issue: the 12-state scenario at issue 23's disturbance (0.01 on the velocities, 0.1
// on the body rates), 30 steps; bytes: the controller file's payload (serialize).
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <string>
#include <vector>

#include "funnel_scenarios.hpp"
#include "funnel_synthesis.hpp"
#include "funnel_tracker.hpp"
#include "lqr.hpp"
#include "tightness.hpp"

using namespace marsyn;
using namespace marsyn::funnel;

namespace {

TrackingProblem full(const std::string& name) {
  if (name == "unicycle") return testing::unicycle(60);
  if (name == "unicycle_at_bound") return testing::unicycle_at_bound(60);
  if (name == "unicycle_near_bound") return testing::unicycle_near_bound();
  if (name == "crane") return testing::crane(40);
  if (name == "bicycle") return testing::bicycle(50);
  if (name == "planar_quadrotor") return testing::planar_quadrotor(50);
  if (name == "quadrotor") return testing::quadrotor(30);
  if (name == "quadrotor_issue") {
    TrackingProblem p = testing::quadrotor(30);
    for (int i = 6; i < 12; ++i) p.tube.w[i] = i < 9 ? 0.01 : 0.1;
    return p;
  }
  throw std::invalid_argument(name);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> names;
  Params extra;
  double w_scale = 1.0, remainder_scale = 1.0;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const auto eq = arg.find('=');
    if (eq == std::string::npos) {
      names.push_back(arg);
      continue;
    }
    const std::string key = arg.substr(0, eq), value = arg.substr(eq + 1);
    if (key == "w_scale" || key == "remainder_scale") {
      (key == "w_scale" ? w_scale : remainder_scale) = std::stod(value);
      continue;
    }
    char* end = nullptr;
    const long l = std::strtol(value.c_str(), &end, 10);
    if (*end == 0 && !value.empty()) {
      extra.set(key, l);
      continue;
    }
    const double d = std::strtod(value.c_str(), &end);
    if (*end == 0 && !value.empty()) extra.set(key, d);
    else if (value == "true" || value == "false") extra.set(key, value == "true");
    else extra.set(key, value);
  }
  if (names.empty()) names = {"unicycle", "crane", "bicycle", "planar_quadrotor", "quadrotor"};
  std::printf("%-17s %-12s %6s %9s %8s %9s %8s %8s  %s\n", "scenario", "enclosure", "steps", "track_s", "fill", "tight_med",
              "call_us", "bytes", "message");
  std::vector<std::string> modes{"mean_value", "second_order"};
  if (extra.has("enclosure")) modes = {extra.text("enclosure", "")};
  for (const std::string& name : names) {
    TrackingProblem p = full(name);
    p.tube.w *= w_scale;
    for (const std::string& mode : modes) {
      Params params = extra;
      params.set("enclosure", mode);
      FunnelTracker tracker(params);
      tracker.scale_remainder_for_tests(remainder_scale);
      const auto t0 = std::chrono::steady_clock::now();
      const TrackResult r = tracker.track(p, {});
      const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      // Steps verified: from the message on failure ("at step k of T"), T on success.
      std::string steps = std::to_string(p.nominal.u.size());
      if (r.status != TrackerStatus::ControllerFound) {
        const auto at = r.message.find("at step ");
        steps = at == std::string::npos ? "-" : r.message.substr(at + 8, r.message.find(' ', at + 8) - at - 8);
        steps = "<" + steps;
      }
      std::string fill = "-", tight = "-";
      const auto f = r.message.find("fill at most ");
      if (f != std::string::npos) fill = r.message.substr(f + 13, r.message.find('%', f) - f - 13) + "%";
      const auto t = r.message.find("median ");
      if (t != std::string::npos) tight = r.message.substr(t + 7, r.message.find('x', t) - t - 7);
      // Cost of one controller call (membership test included) at the nominal states.
      double call_us = 0.0;
      std::size_t bytes = 0;
      if (r.controller) {
        bytes = serialize(dynamic_cast<const FunnelController&>(*r.controller).data()).size();
        const int T = static_cast<int>(p.nominal.u.size()), reps = 200;
        std::vector<double> u(p.dynamics->input_dim());
        const auto c0 = std::chrono::steady_clock::now();
        for (int rep = 0; rep < reps; ++rep)
          for (int k = 0; k < T; ++k) r.controller->input(p.nominal.x[k].data(), k, u.data());
        call_us = 1e6 * std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count() / (reps * T);
      }
      std::printf("%-17s %-12s %6s %9.3f %8s %9s %8.2f %8zu  %s\n", name.c_str(), mode.c_str(), steps.c_str(), secs,
                  fill.c_str(), tight.c_str(), call_us, bytes, r.message.c_str());
      std::fflush(stdout);
    }
  }
  return 0;
}
