#include "input_weights.hpp"

#include <algorithm>
#include <cmath>

namespace marsyn::funnel {

bool saturation_matters(const TrackingProblem& p, const VerifyOutcome& v, double share) {
  for (std::size_t k = 0; k < v.input_boxed.size(); ++k)
    for (std::size_t i = 0; i < v.input_boxed[k].size(); ++i) {
      if (!v.input_boxed[k][i]) continue;
      const double lo = p.input_bounds.lo[i], hi = p.input_bounds.hi[i];
      const FastInterval& h = v.input_hull[k][i];
      if (std::max(h.upper() - hi, lo - h.lower()) > share * (hi - lo)) return true;
    }
  return false;
}

InputReweighting input_aware_weights(const TrackingProblem& p, const LqrGains& g, const VerifyOutcome& v,
                                     std::vector<Eigen::VectorXd>& r_steps, double floor, double margin) {
  InputReweighting out;
  r_steps = g.r;
  const int m = static_cast<int>(p.input_bounds.dim());
  const int T = static_cast<int>(g.r.size());
  const int seen = std::min<int>(static_cast<int>(v.input_hull.size()), T);
  if (seen == 0) return out;
  const std::vector<FastInterval>& at_miss = v.input_hull[static_cast<std::size_t>(seen) - 1];
  for (int k = 0; k < T; ++k) {
    for (int i = 0; i < m; ++i) {
      const double lo = p.input_bounds.lo[i], hi = p.input_bounds.hi[i], uk = p.nominal.u[k][i];
      // Past the miss no hull is known: the feedback's half-width at the miss, about u_k, stands
      // for it, so that one redesign reaches the steps where the nominal's input is near a bound.
      FastInterval h = v.input_hull[static_cast<std::size_t>(std::min(k, seen - 1))][static_cast<std::size_t>(i)];
      if (k >= seen) {
        const double half = 0.5 * (at_miss[i].upper() - at_miss[i].lower());
        h = FastInterval(uk - half, uk + half);
      }
      if (h.lower() >= lo && h.upper() <= hi) continue;
      // The feedback's part of the hull, [uk + a f_lo, uk + a f_hi] once scaled by a: inside
      // U for a <= (hi - uk) / f_hi (f_hi > 0) and a <= (uk - lo) / -f_lo (f_lo < 0).
      const double f_lo = h.lower() - uk, f_hi = h.upper() - uk;
      double a = 1.0;
      if (f_hi > 0) a = std::min(a, std::max(0.0, hi - uk) / f_hi);
      if (f_lo < 0) a = std::min(a, std::max(0.0, uk - lo) / -f_lo);
      a = std::max(floor, margin * a);
      if (!(a < 1.0)) continue;
      const double b = g.bpb[static_cast<std::size_t>(k)][i];
      double& r = r_steps[static_cast<std::size_t>(k)][i];
      const double raised = (r + b) / a - b;
      if (!(raised > r) || !std::isfinite(raised)) continue;
      r = raised;
      ++out.rows;
      if (out.first_step < 0) out.first_step = k;
      out.last_step = k;
    }
  }
  return out;
}

}  // namespace marsyn::funnel
