#pragma once
// Synthesized example agents, computed once per test binary and shared by the tests.
#include <map>
#include <mutex>
#include <string>

#include "abcd_tracker.hpp"
#include "track_scenarios.hpp"

namespace marsyn::abcd::testing {

struct Agent {
  TrackingProblem problem;
  TrackResult result;
};

inline TrackingProblem scenario(const std::string& name) {
  if (name == "drone") return scenarios::drone();
  if (name == "lane") return scenarios::lane_merging();
  if (name == "formation") return scenarios::formation();
  if (name == "vehicle") return scenarios::vehicle();
  if (name == "pendulum") return scenarios::pendulum();
  if (name == "crane") return scenarios::crane(6);  // a shorter crane run keeps the suite fast (bench: 70)
  throw std::invalid_argument(name);
}

inline const Agent& agent(const std::string& name) {
  static std::map<std::string, Agent> cache;
  static std::mutex mu;
  std::lock_guard<std::mutex> lock(mu);
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  Agent a;
  a.problem = scenario(name);
  AbcdTracker tracker;
  TrackOptions o;
  o.threads = 2;
  a.result = tracker.track(a.problem, o);
  return cache.emplace(name, std::move(a)).first->second;
}

}  // namespace marsyn::abcd::testing
