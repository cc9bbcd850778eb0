#pragma once
// report.html: one self-contained page (no network) with an animation of the agents, their tubes,
// the obstacles and goals; margin-to-threshold plots over time for open loop vs feedback; and
// the per-stage figures as a row of the paper's Table 2.
#include <string>

#include <nlohmann/json.hpp>

#include "marsyn/core/verification/verification.hpp"
#include "marsyn/problem.hpp"
#include "marsyn/tracker.hpp"

namespace marsyn {

// Workspace geometry and trajectories for the page, computed from the problem and the runs.
// `enclosures` (optional, per agent): its controller's period enclosures, drawn between the
// samples.
nlohmann::json report_scene(const Problem& problem, const std::vector<NominalTrajectory>& nominal,
                            const VerificationReport* verification,
                            const std::vector<const std::vector<PeriodEnclosure>*>& enclosures = {});

// `result` is the content of result.json; `scene` comes from report_scene().
void write_report_html(const std::string& path, const nlohmann::json& result, const nlohmann::json& scene);

}  // namespace marsyn
