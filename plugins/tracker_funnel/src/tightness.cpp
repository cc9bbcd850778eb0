#include "tightness.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "marsyn/sampled_map.hpp"

namespace marsyn::funnel {
namespace {

double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

Tightness measure_tightness(const Dynamics& f, const FunnelController& ctrl, std::vector<std::vector<double>> verified,
                            int runs, std::uint64_t seed) {
  const FunnelData& d = ctrl.data();
  const int n = d.n, m = d.m, T = d.horizon();
  constexpr int kFine = 16, kPieces = 8;
  Tightness t;
  t.verified = std::move(verified);
  t.sampled.assign(static_cast<std::size_t>(T) + 1, std::vector<double>(n, 0.0));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U01(0, 1);
  std::vector<double> x(n), u(m), w(n), next(n);
  for (int r = 0; r < runs; ++r) {
    const int mode = r % 4;
    for (int i = 0; i < n; ++i) x[i] = U01(rng) < 0.5 ? d.sets[0].lo[i] : d.sets[0].hi[i];
    if (!ctrl.in_set(x.data(), 0)) continue;
    ++t.runs;
    for (int k = 0; k < T; ++k) {
      for (int i = 0; i < n; ++i) t.sampled[k][i] = std::max(t.sampled[k][i], std::fabs(x[i] - d.x_nom[k][i]));
      if (ctrl.input(x.data(), k, u.data()) != ControlStatus::Ok) break;
      for (int q = 0; q < kFine; ++q) {
        const bool redraw = (mode == 0 && k == 0 && q == 0) || (mode == 1 && q % (kFine / kPieces) == 0) || mode == 2;
        if (redraw)
          for (int i = 0; i < n; ++i) w[i] = (U01(rng) < 0.5 ? -1 : 1) * d.w[i];
        if (mode == 3) {
          // Away from the nominal interpolated linearly over the period.
          const double s = static_cast<double>(q) / kFine;
          for (int i = 0; i < n; ++i) {
            const double ref = (1 - s) * d.x_nom[k][i] + s * d.x_nom[k + 1][i];
            w[i] = x[i] >= ref ? d.w[i] : -d.w[i];
          }
        }
        rk4_step<double>(f, x.data(), u.data(), w.data(), d.tau / kFine, 1, next.data());
        x = next;
      }
      if (k + 1 == T)
        for (int i = 0; i < n; ++i) t.sampled[T][i] = std::max(t.sampled[T][i], std::fabs(x[i] - d.x_nom[T][i]));
    }
  }
  std::vector<double> all;
  t.coordinate_median.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    std::vector<double> ratios;
    for (int k = 1; k <= T && k < static_cast<int>(t.verified.size()); ++k) {
      const double s = t.sampled[k][i];
      if (!(s > 1e-9)) continue;
      ratios.push_back(t.verified[k][i] / s);
    }
    t.coordinate_median[i] = median_of(ratios);
    for (double v : ratios) t.max = std::max(t.max, v);
    all.insert(all.end(), ratios.begin(), ratios.end());
  }
  t.median = median_of(all);
  return t;
}

std::string describe(const Tightness& t, const std::vector<std::string>& names) {
  std::ostringstream s;
  s.precision(3);
  s << "median " << t.median << "x, max " << t.max << "x";
  int worst = -1;
  for (int i = 0; i < static_cast<int>(t.coordinate_median.size()); ++i)
    if (worst < 0 || t.coordinate_median[i] > t.coordinate_median[worst]) worst = i;
  if (worst >= 0 && worst < static_cast<int>(names.size()))
    s << " (worst coordinate " << names[worst] << " " << t.coordinate_median[worst] << "x)";
  return s.str();
}

}  // namespace marsyn::funnel
