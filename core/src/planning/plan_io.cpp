#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "marsyn/core/planning/plan_io.hpp"
#include "marsyn/core/problem/config_error.hpp"

namespace marsyn::planning {

namespace {
nlohmann::json rows(const std::vector<Eigen::VectorXd>& v) {
  auto out = nlohmann::json::array();
  for (const auto& r : v) out.push_back(std::vector<double>(r.data(), r.data() + r.size()));
  return out;
}
std::ofstream open(const std::string& path) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path);
  f.precision(17);
  return f;
}
}  // namespace

void write_plan_json(const std::string& path, const Problem& problem, const PlanOutcome& o) {
  nlohmann::json j;
  j["problem"] = problem.name;
  j["source"] = problem.source;
  j["feasible"] = o.feasible;
  j["horizon"] = o.horizon;
  j["tau"] = problem.tau;
  j["status"] = to_string(o.result.status);
  j["solver_message"] = o.result.message;
  j["solve_time_s"] = o.result.solve_time_s;
  j["total_time_s"] = o.total_time_s;
  j["iterations"] = o.result.iterations;
  j["final_violation"] = o.result.max_violation;
  j["min_robust_margin"] = o.check.min_margin;
  j["min_robust_margin_at"] = {{"requirement", o.check.worst}, {"step", o.check.worst_step}};
  j["min_input_margin"] = o.check.min_input_margin;
  j["check"] = o.check.message;
  auto attempts = nlohmann::json::array();
  for (const auto& a : o.attempts)
    attempts.push_back({{"horizon", a.horizon}, {"status", to_string(a.status)}, {"iterations", a.iterations},
                        {"solve_time_s", a.solve_time_s}, {"final_violation", a.max_violation},
                        {"robust", a.check.passed}, {"min_robust_margin", a.check.min_margin},
                        {"message", a.message}});
  j["attempts"] = attempts;
  auto agents = nlohmann::json::array();
  for (size_t i = 0; i < o.nominal.size() && i < problem.agents.size(); ++i) {
    const auto& a = problem.agents[i];
    agents.push_back({{"name", a.name}, {"dynamics", a.dynamics_type},
                      {"state_names", a.dynamics->state_names()}, {"input_names", a.dynamics->input_names()},
                      {"states", rows(o.nominal[i].x)}, {"inputs", rows(o.nominal[i].u)}});
    // The stages' visit knots, in order: part of the plan (read back by read_plan_visits).
    if (!a.stages.empty() && i < o.visits.visit.size() && o.visits.visit[i].size() == a.stages.size()) {
      auto v = nlohmann::json::array();
      for (std::size_t s = 0; s < a.stages.size(); ++s) v.push_back({{"stage", a.stages[s].name}, {"step", o.visits.visit[i][s]}});
      agents.back()["visits"] = v;
    }
  }
  j["agents"] = agents;
  auto f = open(path);
  f << j.dump(1) << "\n";
}

namespace {
nlohmann::json parse_plan(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path, 0, 0, "", "cannot read the plan file (missing or unreadable)");
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw ConfigError(path, 0, 0, "", std::string("not a valid JSON plan: ") + e.what());
  }
  return j;
}
}  // namespace

std::vector<NominalTrajectory> read_plan_json(const std::string& path, const Problem& pb) {
  const nlohmann::json j = parse_plan(path);
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

MissionSchedule read_plan_visits(const std::string& path, const Problem& pb, int horizon) {
  const nlohmann::json j = parse_plan(path);
  auto fail = [&](const std::string& field, const std::string& msg) -> void { throw ConfigError(path, 0, 0, field, msg); };
  const bool any = std::any_of(pb.agents.begin(), pb.agents.end(), [](const AgentSpec& a) { return !a.stages.empty(); });
  const nlohmann::json* agents = j.contains("agents") && j["agents"].is_array() ? &j["agents"] : nullptr;
  bool listed = false;
  if (agents)
    for (const auto& e : *agents) listed = listed || (e.is_object() && e.contains("visits"));
  // A plan written before the knots were part of it was planned at the initial schedule.
  if (!any || !listed) return schedule_missions(pb, horizon);
  MissionSchedule s;
  s.horizon = horizon;
  s.visit.resize(pb.agents.size());
  for (std::size_t i = 0; i < pb.agents.size(); ++i) {
    const AgentSpec& a = pb.agents[i];
    if (a.stages.empty()) continue;
    const std::string field = "agents[" + a.name + "].visits";
    const nlohmann::json* v = nullptr;
    for (const auto& e : *agents)
      if (e.is_object() && e.value("name", "") == a.name && e.contains("visits")) v = &e["visits"];
    if (!v || !v->is_array() || v->size() != a.stages.size())
      fail(field, "expected the " + std::to_string(a.stages.size()) + " stages' visits of " + a.name + ", in order");
    for (std::size_t t = 0; t < a.stages.size(); ++t) {
      const auto& e = (*v)[t];
      if (!e.is_object() || e.value("stage", "") != a.stages[t].name || !e.contains("step") || !e["step"].is_number_integer())
        fail(field + "[" + std::to_string(t) + "]",
             "expected {stage: " + a.stages[t].name + ", step: an integer} (the stages in the problem's order)");
      s.visit[i].push_back(e["step"].get<int>());
    }
  }
  if (const std::string e = schedule_error(pb, s, horizon); !e.empty()) fail("visits", "not a schedule of the problem's stages at T = " + std::to_string(horizon) + ": " + e);
  return s;
}

std::vector<std::string> write_agent_csvs(const std::string& dir, const Problem& problem, const PlanOutcome& o) {
  std::filesystem::create_directories(dir);
  std::vector<std::string> files;
  for (size_t i = 0; i < o.nominal.size() && i < problem.agents.size(); ++i) {
    const auto& a = problem.agents[i];
    const auto& tr = o.nominal[i];
    const std::string path = (std::filesystem::path(dir) / (a.name + ".csv")).string();
    auto f = open(path);
    f << "k,t";
    for (const auto& s : a.dynamics->state_names()) f << "," << s;
    for (const auto& s : a.dynamics->input_names()) f << "," << s;
    f << "\n";
    for (size_t k = 0; k < tr.x.size(); ++k) {
      f << k << "," << std::setprecision(12) << k * problem.tau << std::setprecision(17);
      for (int c = 0; c < tr.x[k].size(); ++c) f << "," << tr.x[k][c];
      for (int c = 0; c < a.m(); ++c) {
        f << ",";
        if (k < tr.u.size()) f << tr.u[k][c];
      }
      f << "\n";
    }
    files.push_back(path);
  }
  return files;
}

}  // namespace marsyn::planning
