#include "tube_fields.hpp"

#include "agent_fields.hpp"

namespace marsyn::loader {

namespace {
bool says_auto(const yaml::Field& f) { return f.present() && f.is_scalar() && f.text() == "auto"; }
}  // namespace

AutoTube read_tube(const yaml::Field& af, const yaml::Field& defaults, double tau, AgentSpec& a, const std::string& sn,
                   const std::string& sm) {
  AutoTube at;
  const int n = a.n(), m = a.m();
  const yaml::Field epsf = agent_field(af, defaults, "eps");
  at.eps = !epsf.present() || says_auto(epsf);
  if (at.eps) a.tube.eps = first_auto_eps(a, tau);
  else a.tube.eps = epsf.positive_vector(n, sn);
  // The grids are optional: only a grid tracker (abcd) reads them, and its assessment asks for
  // them when they are missing. With an auto eps an absent grid follows it.
  const yaml::Field etaf = agent_field(af, defaults, "eta_x"), etauf = agent_field(af, defaults, "eta_u");
  at.eta_x = says_auto(etaf) || (at.eps && !etaf.present());
  at.eta_u = says_auto(etauf) || (at.eps && !etauf.present());
  if (!at.eta_x && etaf.present()) a.tube.eta_x = etaf.positive_vector(n, sn);
  if (!at.eta_u && etauf.present()) a.tube.eta_u = etauf.positive_vector(m, sm);
  auto_grid(a, at);
  return at;
}

}  // namespace marsyn::loader
