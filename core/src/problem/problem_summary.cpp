#include "marsyn/core/problem/problem_summary.hpp"

#include "periodic_fields.hpp"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "marsyn/core/planning/mission.hpp"
#include "marsyn/core/planning/goal_room.hpp"
#include "marsyn/core/planning/workspace_gaps.hpp"
#include "marsyn/number_text.hpp"
#include "marsyn/periodic.hpp"
#include "agent_runs.hpp"

namespace marsyn {

namespace {

// "bodies    tug1, tug2: radius 0.3; drone1: radius 0.2 (two agents keep delta plus both radii, ...)":
// agents grouped by radius, so that a team of hundreds stays one line.
std::string bodies_line(const Problem& pb) {
  // Each agent's bodies in words ("radius 0.3"; "radius 1, cart: footprint 'cart' radius 1.2").
  std::vector<std::pair<std::string, std::vector<std::string>>> by_radius;
  for (std::size_t i = 0; i < pb.agents.size(); ++i) {
    const AgentSpec& a = pb.agents[i];
    std::ostringstream d;
    d.precision(kMessageDigits);
    d << (a.body.empty() ? "" : a.body + ": ") << "radius " << a.radius;
    bool more = false;
    for (const auto& e : pb.extra_bodies) {
      if (e.agent != static_cast<int>(i)) continue;
      more = true;
      d << ", " << e.body << ": "
        << (e.spec.workspace.linear() ? std::string("a linear point") : "footprint '" + e.spec.workspace.footprint_name + "'")
        << " radius " << e.spec.radius;
    }
    if (!(a.radius > 0) && !more) continue;
    auto it = std::find_if(by_radius.begin(), by_radius.end(), [&](const auto& e) { return e.first == d.str(); });
    if (it == by_radius.end()) by_radius.push_back({d.str(), {a.name}});
    else it->second.push_back(a.name);
  }
  if (by_radius.empty()) return "";
  std::ostringstream s;
  s.precision(kMessageDigits);
  s << "bodies    ";
  for (std::size_t k = 0; k < by_radius.size(); ++k) {
    const auto& names = by_radius[k].second;
    s << (k ? "; " : "");
    if (names.size() > 4) s << names.front() << " .. " << names.back() << " (" << names.size() << " agents)";
    else
      for (std::size_t i = 0; i < names.size(); ++i) s << (i ? ", " : "") << names[i];
    s << ": " << by_radius[k].first;
  }
  s << " (a pair keeps delta + both radii; an obstacle " << (pb.delta_bounds > 0 ? "and the state bounds keep their" : "keeps its")
    << " delta + the agent's radius" << (pb.delta_bounds > 0 ? "" : ", the state bounds the radius") << ")\n";
  return s.str();
}

}  // namespace

ConstraintCounts count_constraints(const Problem& pb) {
  ConstraintCounts c;
  // Per body (planning::for_each_requirement): every body against every obstacle, every two bodies
  // of different agents.
  const long n = pb.body_count();
  c.obstacle = static_cast<int>(n * static_cast<long>(pb.obstacles.size()));
  long pairs = n * (n - 1) / 2;
  std::vector<long> per_agent(pb.agents.size(), 0);
  for (int b = 0; b < pb.body_count(); ++b) ++per_agent[static_cast<std::size_t>(pb.body_agent(b))];
  for (long k : per_agent) pairs -= k * (k - 1) / 2;
  c.collision = pb.pairwise_collision ? static_cast<int>(pairs) : 0;
  c.formation = static_cast<int>(pb.formation.size());
  return c;
}

namespace {

// "angles    westbound: theta free, goal a turn of +1.571 (4.712 +- 0.4); ...": for angles left free
// (`any`) and goal arcs half a radian or more from x0, the branch the goal was kept on (the way
// there winds, or the shorter way round): which way each robot turns.
std::string angles_line(const Problem& pb) {
  std::vector<std::string> parts;
  for (const auto& a : pb.agents) {
    const std::vector<bool> periodic = a.dynamics ? a.dynamics->periodic() : std::vector<bool>{};
    const auto names = a.dynamics ? a.dynamics->state_names() : std::vector<std::string>{};
    std::ostringstream d;
    d.precision(kMessageDigits);
    for (int i = 0; i < a.n() && i < static_cast<int>(periodic.size()); ++i) {
      if (!periodic[static_cast<std::size_t>(i)]) continue;
      const double width = a.state_bounds.hi[i] - a.state_bounds.lo[i];
      const bool free = width >= 2 * loader::kFreeTurns * kTurn * (1 - 1e-12);
      const bool any_goal = a.goal.lo[i] <= a.state_bounds.lo[i] && a.goal.hi[i] >= a.state_bounds.hi[i];
      const bool arc = a.goal.hi[i] - a.goal.lo[i] < kTurn;
      const double c = a.goal.center()[i];
      double turn = c - a.x0[i];
      if (std::abs(turn) < 1e-9 * (1 + std::abs(c))) turn = 0;  // rounding residue of the lift
      // Angles left free, and goal arcs half a radian or more away: which way the robot turns.
      if (!free && !(arc && std::abs(turn) >= 0.5)) continue;
      d << (d.tellp() > 0 ? "; " : "") << names[static_cast<std::size_t>(i)] << (free ? " free" : "");
      if (any_goal) d << ", goal any";
      else if (!arc) d << ", goal wider than a turn";
      else
        d << (free ? ", goal" : " goal") << " a turn of " << (turn > 0 ? "+" : "") << number_text(turn) << " (" << number_text(c) << " +- "
          << number_text(0.5 * (a.goal.hi[i] - a.goal.lo[i])) << ")";
    }
    if (d.tellp() > 0) parts.push_back(a.name + ": " + d.str());
  }
  if (parts.empty()) return "";
  std::string line = "angles    ";
  const std::size_t shown = parts.size() > 4 ? 3 : parts.size();
  for (std::size_t i = 0; i < shown; ++i) line += (i ? "; " : "") + parts[i];
  if (shown < parts.size()) line += "; ... (" + std::to_string(parts.size()) + " agents)";
  return line + "\n";
}

// The agent table: each column as wide as its widest cell plus two spaces, so that no value
// (a long vector) runs into the next column. The trackers' own fields (abcd's grid) by name.
std::string agent_table(const Problem& pb, const std::vector<AgentTrackers>& trackers) {
  std::ostringstream s;
  s.precision(kMessageDigits);
  std::vector<std::string> field_names;
  for (const auto& a : pb.agents)
    for (const auto& f : a.fields.items)
      if (std::find(field_names.begin(), field_names.end(), f.name) == field_names.end()) field_names.push_back(f.name);
  std::vector<std::vector<std::string>> rows{{"agent", "dynamics", "n x m", "eps"}};
  // The stated initial sets, in a column of their own when any agent states one.
  const bool initial_sets = std::any_of(pb.agents.begin(), pb.agents.end(), [](const AgentSpec& a) { return a.x0_radius.size() > 0; });
  if (initial_sets) rows[0].push_back("x0 +-");
  rows[0].insert(rows[0].end(), field_names.begin(), field_names.end());
  rows[0].push_back("tracker");
  for (std::size_t i = 0; i < pb.agents.size(); ++i) {
    const AgentSpec& a = pb.agents[i];
    // The tracker's own figures (abcd: tube cells per step and grid inputs), from its assessment.
    std::string tracker = a.tracker.name;
    if (i < trackers.size()) {
      const AgentTrackers& t = trackers[i];
      if (t.automatic) {
        tracker += " (auto";
        for (const auto& f : t.fallbacks) tracker += ", then " + f.name;
        tracker += ")";
      }
      if (!t.assessment.summary.empty()) tracker += ": " + t.assessment.summary;
    }
    std::vector<std::string> row{a.name, a.dynamics_type, std::to_string(a.n()) + " x " + std::to_string(a.m()),
                                 list_text(a.tube.eps)};
    if (initial_sets) row.push_back(a.x0_radius.size() ? list_text(a.x0_radius) : std::string("0"));
    for (const auto& name : field_names) {
      const Eigen::VectorXd v = a.fields.value(name);
      row.push_back(v.size() ? list_text(v) : std::string("-"));
    }
    row.push_back(tracker);
    rows.push_back(std::move(row));
  }
  // Consecutive agents with the same row share one (a field of 1000 alike robots is one line).
  {
    std::vector<std::string> names, keys;
    for (std::size_t r = 1; r < rows.size(); ++r) {
      names.push_back(rows[r][0]);
      std::string key;
      for (std::size_t c = 1; c < rows[r].size(); ++c) key += rows[r][c] + '\x1f';
      keys.push_back(std::move(key));
    }
    std::vector<std::vector<std::string>> grouped{rows[0]};
    for (const AgentRun& run : agent_runs(names, keys)) {
      grouped.push_back(rows[run.first + 1]);
      grouped.back()[0] = run.label;
    }
    rows = std::move(grouped);
  }
  std::vector<std::size_t> width(rows[0].size(), 0);
  for (const auto& r : rows)
    for (std::size_t c = 0; c < r.size(); ++c) width[c] = std::max(width[c], r[c].size() + 2);
  for (const auto& r : rows) {
    for (std::size_t c = 0; c + 1 < r.size(); ++c) s << std::left << std::setw(static_cast<int>(width[c])) << r[c];
    s << r.back() << "\n";
  }
  return s.str();
}

}  // namespace

std::string summarize(const Problem& pb, const std::vector<AgentTrackers>& trackers) {
  std::ostringstream s;
  s.precision(kMessageDigits);
  const ConstraintCounts c = count_constraints(pb);
  s << "problem   " << pb.name << "  (" << pb.source << ")\n";
  s << "agents    " << pb.agents.size() << "    product system: " << pb.product_state_dim() << " states, "
    << pb.product_input_dim() << " inputs\n";
  s << "time      tau = " << pb.tau << " s, horizon T = " << pb.horizon << " steps (" << pb.tau * pb.horizon
    << " s)\n";
  s << "safety    delta = " << pb.delta;
  if (pb.delta_obstacles >= 0) s << " between agents, " << pb.delta_obstacles << " to obstacles";
  if (pb.delta_bounds > 0) s << ", " << pb.delta_bounds << " to the state bounds";
  s << " (" << (pb.delta_norm == Norm::Inf ? "inf-norm" : "2-norm")
    << (pb.workspace_dim == 3 ? ", in space: x, y, z; obstacles are vertical prisms" : "") << ")\n";
  s << bodies_line(pb);
  s << angles_line(pb);
  s << "guarantee " << (pb.guarantee == Guarantee::Continuous
                            ? "continuous (every t in [0, T tau], between the samples too)"
                            : "sampled (t = k tau only, the paper's semantics)")
    << "\n";
  s << "plugins   planner "
    << (pb.warm_start_planner.name.empty() ? "" : pb.warm_start_planner.name + " -> ") << pb.planner.name << ", tracker " << pb.tracker.name << ", obstacle distances "
    << (pb.collision.name.empty() ? "exact (core)" : pb.collision.name) << "\n\n";
  s << agent_table(pb, trackers);
  // A W that grows with the state or input (docs/problem-format.md): its formula and its largest
  // value, which a tracker that cannot read W(x, u) takes.
  for (const auto& a : pb.agents) {
    if (!a.tube.state_dependent()) continue;
    s << "disturbance " << a.name << ": W = " << list_text(a.tube.w_base);
    for (const auto& g : a.tube.w_growth) s << " + " << list_text(g.gain) << " |" << g.name << "|";
    s << ", at most " << list_text(a.tube.w) << " over X and U (what a tracker that cannot read W(x, u) takes)\n";
  }
  s << "\nconstraints per step: " << c.per_step() << " (obstacle " << c.obstacle << ", collision " << c.collision
    << ", formation " << c.formation << "); obstacles " << pb.obstacles.size() << "\n";
  s << "constraints over the horizon: " << static_cast<long long>(c.per_step()) * (pb.horizon + 1)
    << " inequalities + " << pb.product_input_dim() * pb.horizon * 2 << " input bounds + "
    << pb.product_state_dim() * 2 << " goal bounds\n";
  // Missions (docs/tasks.md): each agent's stages in order, with the initial schedule's knots at
  // T (before a plan: the plan starts there and may move every knot not fixed by its window).
  if (std::any_of(pb.agents.begin(), pb.agents.end(), [](const AgentSpec& a) { return !a.stages.empty(); })) {
    const planning::MissionSchedule sched = planning::schedule_missions(pb, pb.horizon);
    s << "mission   stages in order (initial visit step at T = " << pb.horizon << "; the plan re-times the knots its windows leave free)\n";
    for (std::size_t i = 0; i < pb.agents.size(); ++i) {
      const AgentSpec& a = pb.agents[i];
      if (a.stages.empty()) continue;
      s << "  " << a.name << ":";
      for (std::size_t k = 0; k < a.stages.size(); ++k) {
        const MissionStage& st = a.stages[k];
        s << (k ? " ->" : "") << " " << st.name << " @" << sched.visit[i][k];
        if (st.dwell > 0) s << "+" << st.dwell;
        if (st.not_before > 1 || st.by >= 0)
          s << " [" << st.not_before << ", " << (st.by >= 0 ? std::to_string(st.by) : std::string("T")) << "]";
        if (!st.team.empty()) s << " (team " << st.team << ")";
      }
      s << " -> goal @" << pb.horizon << "\n";
    }
    if (!sched.feasible) s << "warning: " << sched.why << "\n";
  }
  // The narrowest gaps first; a room of many alike gaps (crop beds, shelves) names a few.
  std::size_t off_the_way = 0;
  std::vector<planning::NarrowGap> gaps = planning::gaps_on_the_way(pb, &off_the_way);
  std::stable_sort(gaps.begin(), gaps.end(), [](const auto& a, const auto& b) { return a.width < b.width; });
  constexpr std::size_t kGaps = 8;
  for (std::size_t g = 0; g < gaps.size() && g < kGaps; ++g) s << "warning: " << planning::describe(gaps[g]) << "\n";
  if (gaps.size() > kGaps)
    s << "warning: " << gaps.size() - kGaps << " more closed gaps, each at least " << gaps[kGaps].width << " wide\n";
  // Said once, not as a warning: a user who sees a narrow passage on a map may wonder.
  if (off_the_way > 0)
    s << "gaps: " << off_the_way << " closed " << (off_the_way == 1 ? "gap lies" : "gaps lie")
      << " off every agent's shortest way (not a cause)\n";
  std::size_t crowded = 0;
  for (const auto& c : planning::crowded_starts(pb, 5, &crowded)) s << "warning: " << planning::describe(c, pb) << "\n";
  if (crowded > 5) s << "warning: " << crowded - 5 << " more crowded starts\n";
  std::size_t goals = 0;
  for (const auto& c : planning::crowded_goals(pb, 5, &goals)) s << "warning: " << planning::describe(c, pb) << "\n";
  if (goals > 5) s << "warning: " << goals - 5 << " more goals without room\n";
  return s.str();
}

}  // namespace marsyn
