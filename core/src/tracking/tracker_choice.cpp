#include "marsyn/core/tracking/tracker_choice.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "marsyn/core/parallel_tasks.hpp"
#include "marsyn/core/problem/config_error.hpp"

namespace marsyn {

std::map<std::string, std::string> recorded_trackers(const std::string& dir) {
  std::map<std::string, std::string> out;
  std::ifstream in(std::filesystem::path(dir) / "result.json");
  if (!in) return out;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    for (const auto& a : j.at("agents"))
      if (a.contains("name") && a["name"].is_string() && a.contains("tracker") && a["tracker"].is_object() &&
          a["tracker"].contains("name") && a["tracker"]["name"].is_string())
        out[a["name"].get<std::string>()] = a["tracker"]["name"].get<std::string>();
  } catch (const std::exception&) {
    out.clear();  // not marsyn's result.json: the agents' own trackers
  }
  return out;
}

namespace {

// `marsyn track` records the tracker that wrote <agent>.ctrl in <agent>.track.json (under
// `tracker: auto`, possibly the fallback): "" when absent or unreadable.
std::string tracked_by(const std::string& dir, const std::string& agent) {
  std::ifstream in(std::filesystem::path(dir) / (agent + ".track.json"));
  if (!in) return "";
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    if (j.contains("tracker") && j["tracker"].is_object() && j["tracker"].contains("name") && j["tracker"]["name"].is_string())
      return j["tracker"]["name"].get<std::string>();
  } catch (const std::exception&) {
  }
  return "";
}

}  // namespace

std::vector<std::shared_ptr<const Controller>> read_agent_controllers(const Problem& pb, TrackerInstances& trackers,
                                                                      const std::string& dir, bool missing_ok) {
  auto recorded = recorded_trackers(dir);  // a solve folder's result.json
  for (const auto& a : pb.agents)
    if (!recorded.count(a.name))
      if (std::string t = tracked_by(dir, a.name); !t.empty()) recorded[a.name] = t;
  // The trackers first, on this thread (TrackerInstances creates them on demand).
  std::vector<std::shared_ptr<const Tracker>> by_agent;
  for (const auto& a : pb.agents) {
    const auto it = recorded.find(a.name);
    const PluginChoice choice = it == recorded.end() || it->second == a.tracker.name ? a.tracker : PluginChoice{it->second, {}};
    try {
      by_agent.push_back(trackers.get(choice));
    } catch (const std::exception& e) {
      throw ConfigError((std::filesystem::path(dir) / "result.json").string(), 0, 0, "agents." + a.name + ".tracker",
                        "the controller of " + a.name + " was written by the tracker '" + choice.name +
                            "', which could not be created: " + e.what());
    }
  }
  // Then the files, on every core: reading and checking large tables was a fifth of a short
  // `marsyn verify`. read_controller is const and reads only its file (trackers already track
  // agents on several threads). The first agent's error in problem order is the one reported.
  const int n = static_cast<int>(pb.agents.size());
  std::vector<std::shared_ptr<const Controller>> out(static_cast<size_t>(n));
  parallel_tasks(n, static_cast<int>(std::thread::hardware_concurrency()), [&](int i) {
    const std::string file = (std::filesystem::path(dir) / (pb.agents[i].name + ".ctrl")).string();
    if (missing_ok && !std::filesystem::exists(file)) return;
    try {
      out[static_cast<size_t>(i)] = by_agent[static_cast<size_t>(i)]->read_controller(file);
    } catch (const std::exception& e) {
      throw ConfigError(file, 0, 0, "", *e.what() ? e.what() : "unreadable controller file");
    }
  });
  for (int i = 0; i < n; ++i) {
    const AgentSpec& a = pb.agents[i];
    const std::string file = (std::filesystem::path(dir) / (a.name + ".ctrl")).string();
    const std::shared_ptr<const Controller>& c = out[static_cast<size_t>(i)];
    if (!c && missing_ok && !std::filesystem::exists(file)) continue;
    // A controller of another problem (or a renamed file) must not be run on this agent's vectors.
    if (!c || c->state_dim() != a.n() || c->input_dim() != a.m())
      throw ConfigError(file, 0, 0, "",
                        "this controller has " + std::to_string(c ? c->state_dim() : 0) + " states and " +
                            std::to_string(c ? c->input_dim() : 0) + " inputs, but agent " + a.name + " (" +
                            a.dynamics_type + ") has " + std::to_string(a.n()) + " and " + std::to_string(a.m()));
  }
  return out;
}

FallbackTrack track_with_fallback(TrackerInstances& trackers, const AgentSpec& agent, const AgentTrackers* choice,
                                  const TrackingProblem& problem, const TrackOptions& options,
                                  const std::function<void(const std::string&)>& log) {
  FallbackTrack out;
  out.automatic = choice && choice->automatic;
  std::vector<PluginChoice> order{agent.tracker};
  if (out.automatic) order.insert(order.end(), choice->fallbacks.begin(), choice->fallbacks.end());
  for (std::size_t c = 0; c < order.size(); ++c) {
    out.tracker = order[c].name;
    out.tried.push_back(out.tracker);
    if (log) log("[track] " + agent.name + " with " + out.tracker + (out.automatic ? " (tracker: auto)" : ""));
    out.instance = trackers.get(order[c]);
    out.result = out.instance->track(problem, options);
    if (out.result.status != TrackerStatus::NoController || c + 1 == order.size()) break;
    if (log)
      log("[track] " + out.tracker + " found no controller for " + agent.name + "; tracker: auto falls back to " +
          order[c + 1].name);
  }
  return out;
}

}  // namespace marsyn
