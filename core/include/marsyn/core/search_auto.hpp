#pragma once
// `eps: auto` inside the search (docs/parameters.md): after a round in which every agent got a
// controller, an auto agent's eps becomes the tube its controller was seen to keep at the
// samples plus a stated margin (kAutoEpsMargin), and the team is planned and tracked again, at
// most kAutoEpsIterations times; a narrower round that fails is dropped and the last verified one
// kept. The trackers' guarantee never rests on the derived value: every round is tracked and
// certified afresh.
#include <string>

#include "marsyn/problem.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn::search {

// The half-widths of the tube `controller` keeps at the samples around `nominal`: over its period
// enclosures that begin or end at a sample, the largest distance of the state box from the
// nominal state there. Empty when the controller has no period enclosures.
Eigen::VectorXd kept_tube(const Controller& controller, const NominalTrajectory& nominal, double tau);
// The tracker's own figure of that tube when it states one (TrackerStats::tube_kept: the funnel's
// invariant sets are wider than what the closed loop reaches, on purpose), else the above.
Eigen::VectorXd kept_tube(const TrackResult& result, const NominalTrajectory& nominal, double tau);

// An auto agent's next eps: (1 + kAutoEpsMargin) x kept, no wider than its eps, no narrower than
// its disturbance's one-period push w tau nor kAutoEpsFloor x `first` (the loader's first value:
// a tracker whose tube scales with eps itself, as the funnel's initial box and weights do, would
// otherwise only measure its own parametrization, round after round); empty when no coordinate
// would narrow by 10 % or more.
Eigen::VectorXd narrower_auto_eps(const AgentSpec& agent, const Eigen::VectorXd& kept, double tau,
                                  const Eigen::VectorXd& first);

// Which rule set each coordinate of `next` (narrower_auto_eps's result), for the summary:
// "+25 %", or "+25 %; half the first value in x, y" where the floor, the disturbance's push or
// the current eps decided instead (a kept tube of 0.035 does not give an eps of 0.074 by +25 %).
std::string auto_eps_rule_text(const AgentSpec& agent, const Eigen::VectorXd& kept, double tau, const Eigen::VectorXd& first,
                               const Eigen::VectorXd& next, const std::vector<std::string>& names);

}  // namespace marsyn::search
