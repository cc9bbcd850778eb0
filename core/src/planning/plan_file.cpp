#include "marsyn/core/planning/plan_file.hpp"

#include <fstream>

#include <nlohmann/json.hpp>

#include "marsyn/core/problem/config_error.hpp"

namespace marsyn {

std::vector<NominalTrajectory> read_plan_json(const std::string& path, const Problem& pb) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path, 0, 0, "", "cannot read the plan file (missing or unreadable)");
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw ConfigError(path, 0, 0, "", std::string("not a valid JSON plan: ") + e.what());
  }
  auto fail = [&](const std::string& field, const std::string& msg) -> void {
    throw ConfigError(path, 0, 0, field, msg);
  };
  if (!j.is_object() || !j.contains("agents") || !j["agents"].is_array()) fail("agents", "expected a list of agents");
  std::vector<NominalTrajectory> out;
  for (const auto& a : pb.agents) {
    const nlohmann::json* found = nullptr;
    for (const auto& e : j["agents"])
      if (e.is_object() && e.value("name", "") == a.name) found = &e;
    if (!found) fail("agents", "the plan has no agent '" + a.name + "' of the problem " + pb.source);
    NominalTrajectory t;
    t.agent = a.name;
    auto rows = [&](const char* key, int dim, std::vector<Eigen::VectorXd>& dst) {
      const std::string field = "agents[" + a.name + "]." + key;
      if (!found->contains(key) || !(*found)[key].is_array()) fail(field, "expected a list of vectors");
      for (const auto& r : (*found)[key]) {
        if (!r.is_array() || static_cast<int>(r.size()) != dim)
          fail(field, "expected vectors of " + std::to_string(dim) + " numbers (the agent's dynamics '" +
                          a.dynamics_type + "')");
        Eigen::VectorXd v(dim);
        for (int c = 0; c < dim; ++c) {
          if (!r[c].is_number()) fail(field, "expected numbers");
          v[c] = r[c].get<double>();
        }
        dst.push_back(v);
      }
    };
    rows("states", a.n(), t.x);
    rows("inputs", a.m(), t.u);
    if (t.x.size() != t.u.size() + 1 || t.u.empty())
      fail("agents[" + a.name + "]", "expected T + 1 states and T inputs, got " + std::to_string(t.x.size()) +
                                         " and " + std::to_string(t.u.size()));
    if (!out.empty() && out.front().u.size() != t.u.size())
      fail("agents[" + a.name + "]", "all agents must share one horizon");
    out.push_back(std::move(t));
  }
  return out;
}

}  // namespace marsyn
