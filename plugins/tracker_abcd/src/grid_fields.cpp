#include "grid_fields.hpp"

#include <algorithm>
#include <cmath>

#include "marsyn/number_text.hpp"

namespace marsyn::abcd {

std::vector<AgentFieldSpec> grid_field_specs() {
  return {{kEtaX, false, "abcd's state grid: the cell size per state coordinate (at most eps), or auto"},
          {kEtaU, true, "abcd's input grid: the spacing per input over U, or auto"}};
}

std::string follow_tube(AgentSpec& a, TubeChange change) {
  AgentField* eta_x = a.fields.find(kEtaX);
  AgentField* eta_u = a.fields.find(kEtaU);
  if (change == TubeChange::Narrowed) {
    if (eta_x && eta_x->value.size() == a.tube.eps.size()) eta_x->value = eta_x->value.cwiseMin(a.tube.eps);
    return {};
  }
  const bool auto_x = eta_x && eta_x->automatic, auto_u = eta_u && eta_u->automatic;
  const int n = a.n(), m = a.m();
  const double cells = std::clamp(std::floor(std::pow(2e5, 1.0 / std::max(1, n))), 4.0, 16.0);
  const double points = std::clamp(std::floor(std::pow(400.0, 1.0 / std::max(1, m))), 4.0, 20.0);
  if (auto_x) eta_x->value = 2 * a.tube.eps / cells;
  if (auto_u) eta_u->value = (a.input_bounds.hi - a.input_bounds.lo) / points;
  std::string rule;
  if (auto_x) rule = "eta_x = 2 eps / " + std::to_string(static_cast<int>(cells)) + " (cells per coordinate)";
  if (auto_u) rule += (rule.empty() ? "" : "; ") + std::string("eta_u = U's range / ") + std::to_string(static_cast<int>(points));
  return rule;
}

std::vector<std::string> grid_warnings(const AgentSpec& a) {
  std::vector<std::string> out;
  const Eigen::VectorXd eta_x = a.fields.value(kEtaX);
  if (eta_x.size() != a.n()) return out;
  const auto names = a.dynamics ? a.dynamics->state_names() : std::vector<std::string>{};
  for (int k = 0; k < a.n(); ++k)
    if (eta_x[k] > a.tube.eps[k]) {
      const std::string where = k < static_cast<int>(names.size()) ? "'" + names[k] + "'" : "coordinate " + std::to_string(k);
      out.push_back("eta_x " + number_text(eta_x[k], 4) + " in " + where + " exceeds eps " + number_text(a.tube.eps[k], 4) +
                    ": no grid cell fits the tube; a grid tracker (abcd) cannot work (eps / 8 = " +
                    number_text(a.tube.eps[k] / 8, 4) + " would)");
    }
  return out;
}

}  // namespace marsyn::abcd
