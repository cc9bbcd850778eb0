#pragma once
// The exported C of a funnel controller against the C++ controller (docs/deploy.md): sampled
// (x, k) answered by both, compared bit for bit (status, input) and verdict for verdict (the
// monitor <prefix>_inside against FunnelController::in_set). Used by export_test.cpp on the test
// scenarios and by funnel_export_check on the examples' controllers (tests/deploy).
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <sstream>

#include "deploy/c_answers.hpp"
#include "marsyn/periodic.hpp"
#include "export_c.hpp"

namespace marsyn::funnel::testing {

struct ExportComparison {
  std::string error;  // export, compile or run failure
  long queries = 0, mismatches = 0, boundary = 0;
  long status[3] = {0, 0, 0};  // Ok, OutsideDomain, OutsideHorizon (C++)
  long inside = 0, outside = 0;  // the monitor's verdicts (C++)
  long long const_bytes = 0;
  std::string first_mismatches;  // up to five, one per line
};

// A point of V_k's boundary along a random ray from a point of V_k: bisection on the C++ test to
// two adjacent doubles t_in < t_out of the ray parameter; returns x at one of them.
inline bool boundary_point(const FunnelController& c, int k, std::mt19937_64& rng, std::vector<double>& x) {
  const FunnelData& d = c.data();
  const StepSet& s = d.sets[static_cast<size_t>(k)];
  const int n = d.n;
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<double> from(static_cast<size_t>(n)), dir(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    from[static_cast<size_t>(i)] = s.kind == kBox ? 0.5 * (s.lo[i] + s.hi[i]) : s.c[static_cast<size_t>(i)];
    dir[static_cast<size_t>(i)] = d.eps[static_cast<size_t>(i)] * unit(rng);
  }
  auto at = [&](double t) {
    for (int i = 0; i < n; ++i) x[static_cast<size_t>(i)] = from[static_cast<size_t>(i)] + t * dir[static_cast<size_t>(i)];
    return c.in_set(x.data(), k);
  };
  double lo = 0.0, hi = 4.0;
  if (!at(lo) || at(hi)) return false;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (at(mid) ? lo : hi) = mid;
  }
  at(rng() & 1 ? lo : hi);
  if (rng() % 4 == 0) {  // one coordinate one ulp off
    double& v = x[rng() % static_cast<unsigned>(n)];
    v = std::nextafter(v, (rng() & 1) ? INFINITY : -INFINITY);
  }
  return true;
}

// Queries: around the nominal (inside and outside V_k), on V_k's boundary (adjacent doubles either
// side), on the faces of box_k, non-finite and huge coordinates, k before, in and after the
// horizon (k = T asks the monitor only) and at INT_MIN / INT_MAX.
inline std::vector<deploy_test::CQuery> funnel_queries(const FunnelController& c, int count, std::uint64_t seed,
                                                       long* boundary) {
  const FunnelData& d = c.data();
  const int n = d.n, T = d.horizon();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const double specials[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                             -std::numeric_limits<double>::infinity(), 1e300, -1e300, 1e19};
  std::vector<deploy_test::CQuery> out;
  for (int q = 0; q < count; ++q) {
    deploy_test::CQuery Q;
    Q.k = static_cast<std::int32_t>(rng() % static_cast<std::uint64_t>(T + 4)) - 2;  // -2 .. T+1
    if (rng() % 100 == 0) Q.k = (rng() & 1) ? INT_MAX : INT_MIN;
    const int kc = std::clamp<int>(Q.k, 0, T);
    const StepSet& s = d.sets[static_cast<size_t>(kc)];
    Q.x.resize(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i)
      Q.x[static_cast<size_t>(i)] = d.x_nom[static_cast<size_t>(kc)][static_cast<size_t>(i)] + 1.3 * d.eps[static_cast<size_t>(i)] * unit(rng);
    const int kind = static_cast<int>(rng() % 20);
    if (kind < 3) {
      Q.k = kc;
      if (boundary_point(c, kc, rng, Q.x)) ++*boundary;
    } else if (kind == 3) {  // a face of box_k, maybe one ulp off
      const int i = static_cast<int>(rng() % static_cast<unsigned>(n));
      double v = (rng() & 1) ? s.lo[i] : s.hi[i];
      if (rng() % 3 == 1) v = std::nextafter(v, -INFINITY);
      else if (rng() % 2 == 1) v = std::nextafter(v, INFINITY);
      Q.x[static_cast<size_t>(i)] = v;
    } else if (kind == 4) {
      Q.x[rng() % static_cast<unsigned>(n)] = specials[rng() % (sizeof specials / sizeof specials[0])];
    } else if (kind == 5) {
      for (int i = 0; i < n; ++i) Q.x[static_cast<size_t>(i)] += 20.0 * d.eps[static_cast<size_t>(i)] * unit(rng);
    } else if (kind < 12) {  // near V_k's centre (the nominal for the initial box), mostly inside
      const std::vector<double>& centre = s.kind == kBox ? d.x_nom[static_cast<size_t>(kc)] : s.c;
      for (int i = 0; i < n; ++i)
        Q.x[static_cast<size_t>(i)] = centre[static_cast<size_t>(i)] + 0.05 * d.eps[static_cast<size_t>(i)] * unit(rng);
    }
    out.push_back(std::move(Q));
  }
  return out;
}

// turn_angles: every query's periodic coordinates moved by whole turns (-2, -1, 1 or 3), as a
// sensor that reports an angle modulo a turn would give them.
inline ExportComparison compare_export(const FunnelController& c, const std::filesystem::path& dir, const std::string& prefix,
                                       int count, std::uint64_t seed, bool turn_angles = false) {
  ExportComparison r;
  std::filesystem::remove_all(dir);
  ExportRequest req;
  req.format = "c";
  req.out_dir = dir.string();
  req.prefix = prefix;
  const ExportResult e = c.export_to(req);
  if (!e.ok) {
    r.error = e.message;
    return r;
  }
  r.const_bytes = e.const_data_bytes;
  const FunnelData& d = c.data();
  auto qs = funnel_queries(c, count, seed, &r.boundary);
  if (turn_angles) {
    const double turns[] = {-2, -1, 1, 3};
    std::mt19937_64 rng(seed + 1);
    for (auto& Q : qs)
      for (std::size_t i = 0; i < d.periodic.size(); ++i)
        if (d.periodic[i]) Q.x[i] += turns[rng() % 4] * kTurn;
  }
  std::vector<deploy_test::CAnswer> answers;
  r.error = deploy_test::answer_in_c(dir, prefix, d.n, d.m, qs, answers);
  if (!r.error.empty()) return r;
  std::vector<double> u(static_cast<size_t>(d.m));
  for (size_t q = 0; q < qs.size(); ++q) {
    const auto& Q = qs[q];
    const auto& A = answers[q];
    std::fill(u.begin(), u.end(), 0.0);
    const ControlStatus s = c.input(Q.x.data(), Q.k, u.data());
    const bool inside = c.in_set(Q.x.data(), Q.k);
    ++r.status[static_cast<int>(s)];
    ++(inside ? r.inside : r.outside);
    ++r.queries;
    bool same = A.status == static_cast<std::int32_t>(s) && A.inside == (inside ? 1 : 0);
    if (same && s == ControlStatus::Ok) same = std::memcmp(u.data(), A.u.data(), sizeof(double) * u.size()) == 0;
    if (!same && ++r.mismatches <= 5) {
      std::ostringstream o;
      o.precision(17);
      o << "k = " << Q.k << ", x =";
      for (double v : Q.x) o << " " << v;
      o << ": C status " << A.status << " inside " << A.inside << ", C++ " << static_cast<int>(s) << " inside " << inside << "\n";
      r.first_mismatches += o.str();
    }
  }
  return r;
}

}  // namespace marsyn::funnel::testing
