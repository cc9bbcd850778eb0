// The stages behind the front door (setup.hpp); the outer search, Setup::solve, is in solve.cpp.
#include "marsyn/core/setup.hpp"

#include <stdexcept>

namespace marsyn {
namespace {

// A shared pointer that does not own: the caller keeps `loaded` alive.
std::shared_ptr<const LoadedProblem> borrowed(const LoadedProblem& loaded) {
  return std::shared_ptr<const LoadedProblem>(std::shared_ptr<const LoadedProblem>{}, &loaded);
}

}  // namespace

SolveOptions solve_options_for(const LoadedProblem& loaded) {
  SolveOptions so;
  if (loaded.search_time_limit_s) so.time_limit_s = *loaded.search_time_limit_s;
  return so;
}

Setup::Setup(std::shared_ptr<const LoadedProblem> loaded) : loaded_(std::move(loaded)), trackers_(loaded_->registry) {}

Setup::Setup(LoadedProblem&& loaded) : Setup(std::make_shared<const LoadedProblem>(std::move(loaded))) {}

Setup::Setup(const LoadedProblem& loaded) : Setup(borrowed(loaded)) {}

const Planner& Setup::planner(const PluginChoice& choice) {
  for (const auto& [c, p] : planners_)
    if (c.name == choice.name && c.params.values() == choice.params.values()) return *p;
  planners_.emplace_back(choice, loaded_->registry->create<Planner>(choice.name, choice.params));
  return *planners_.back().second;
}

planning::PlanOutcome Setup::plan(planning::PlanSearchOptions options) { return plan(problem(), std::move(options)); }

planning::PlanOutcome Setup::plan(const Problem& problem, planning::PlanSearchOptions options) {
  const Planner& main = planner(problem.planner);
  options.warm_start_planner = problem.warm_start_planner.name.empty() ? nullptr : &planner(problem.warm_start_planner);
  return planning::plan(problem, main, options);
}

std::vector<NominalTrajectory> Setup::nominal(planning::PlanSearchOptions options) {
  const planning::PlanOutcome out = plan(std::move(options));
  if (!out.feasible) throw std::runtime_error("planning failed: " + out.check.message);
  return out.nominal;
}

FallbackTrack Setup::track(int agent, const NominalTrajectory& nominal, TrackOptions options, const Log& log) {
  const auto i = static_cast<std::size_t>(agent);
  options.memory_budget_bytes = loaded_->memory_budget.bytes;
  const AgentTrackers* choice = i < loaded_->trackers.size() ? &loaded_->trackers[i] : nullptr;
  return track_with_fallback(trackers_, problem().agents.at(i), choice, tracking_problem(problem(), agent, nominal),
                             options, log);
}

std::vector<AgentOutcome> Setup::track(const Problem& problem, const std::vector<NominalTrajectory>& nominal,
                                       const SolveOptions& options) {
  return track_agents(problem, nominal, trackers_.for_agents(problem), options, loaded_->memory_budget);
}

CertificationReport Setup::certify(const Problem& problem, const std::vector<AgentOutcome>& agents) const {
  return marsyn::certify(problem, controllers_of(agents));
}

VerificationReport Setup::verify(const Problem& problem, const std::vector<NominalTrajectory>& nominal,
                                 const std::vector<std::shared_ptr<const Controller>>& controllers,
                                 const VerificationOptions& options) const {
  return marsyn::verify(problem, nominal, controllers, options);
}

std::vector<std::shared_ptr<const Controller>> Setup::read_controllers(const std::string& dir) {
  return read_agent_controllers(problem(), trackers_, dir);
}

GlobalAbcdEstimate Setup::global_baseline(const Problem& problem, const SolveOptions& options, const Log& log) {
  return attempt_global_abcd(problem, trackers_, options, log);
}

std::vector<std::shared_ptr<const Controller>> controllers_of(const std::vector<AgentOutcome>& agents) {
  std::vector<std::shared_ptr<const Controller>> out;
  for (const auto& a : agents) out.push_back(a.track.controller);
  return out;
}

}  // namespace marsyn
