#include "tube_fields.hpp"

#include "agent_fields.hpp"
#include "marsyn/core/problem/tracker_fields.hpp"

namespace marsyn::loader {

namespace {
bool says_auto(const yaml::Field& f) { return f.present() && f.is_scalar() && f.text() == "auto"; }

// A word where `auto` or numbers may stand ("eps: fine") is most likely a misspelt `auto`: the
// message names both choices (the list reader's own would name only the list).
void refuse_other_word(const yaml::Field& f, int count) {
  if (f.present() && f.is_scalar() && !says_auto(f))
    f.fail("expected auto or a list of " + std::to_string(count) + " positive numbers, got '" + f.text() + "'");
}
}  // namespace

AutoTube read_tube(const yaml::Field& af, const yaml::Field& defaults, double tau, AgentSpec& a, const std::string& sn,
                   const std::string& sm, const std::vector<AgentFieldSpec>& fields, TrackerInstances& trackers) {
  AutoTube at;
  const int n = a.n(), m = a.m();
  const yaml::Field epsf = agent_field(af, defaults, "eps");
  refuse_other_word(epsf, n);
  at.eps = !epsf.present() || says_auto(epsf);
  if (at.eps) a.tube.eps = first_auto_eps(a, tau);
  else a.tube.eps = epsf.positive_vector(n, sn);
  // The trackers' own fields (abcd's grid) are optional: only their owner reads them, and its
  // assessment asks for them when they are missing. With an auto eps an absent one follows it.
  for (const auto& spec : fields) {
    const yaml::Field f = agent_field(af, defaults, spec.name);
    refuse_other_word(f, spec.per_input ? m : n);
    AgentField field{spec.name, {}, says_auto(f) || (at.eps && !f.present())};
    if (!field.automatic && f.present()) field.value = f.positive_vector(spec.per_input ? m : n, spec.per_input ? sm : sn);
    if (field.automatic) at.fields.push_back(spec.name);
    a.fields.items.push_back(std::move(field));
  }
  at.field_rule = follow_tube(trackers, a, TubeChange::Set);
  return at;
}

}  // namespace marsyn::loader
