#include "funnel_controller.hpp"

#include "marsyn/periodic.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "marsyn/binary_file.hpp"
#include "marsyn/period_enclosure_file.hpp"
#include "membership.hpp"

namespace marsyn::funnel {
namespace {

constexpr char kMagic[8] = {'M', 'A', 'R', 'S', 'Y', 'N', 'F', 'T'};
constexpr std::uint32_t kMaxDim = 64, kMaxSteps = 1u << 20;

// One heap block holding `bytes` (glibc's malloc: 8 bytes of header, 16-byte granules, 32 at least).
double block(std::size_t bytes) {
  if (bytes == 0) return 0.0;
  return static_cast<double>(std::max<std::size_t>(32, (bytes + 8 + 15) / 16 * 16));
}
template <class T> double block_of(const std::vector<T>& v) { return block(v.capacity() * sizeof(T)); }
double block_of(const Eigen::VectorXd& v) { return block(static_cast<std::size_t>(v.size()) * sizeof(double)); }
double block_of(const std::string& s) { return s.capacity() > 15 ? block(s.capacity() + 1) : 0.0; }

// Doubles in a block, as block() counts them.
double doubles(long count) { return block(static_cast<std::size_t>(std::max(0L, count)) * sizeof(double)); }

}  // namespace

double heap_bytes(const FunnelController& c) {
  const FunnelData& d = c.data();
  double b = block(sizeof(FunnelController)) + block_of(d.dist.base()) + block_of(d.dist.growth()) + block_of(d.dynamics_type) + block_of(d.agent) + block_of(d.eps) +
             block_of(d.w) + block_of(d.u_lo) + block_of(d.u_hi) + block_of(d.periodic);
  for (const DisturbanceGrowth& g : d.dist.growth()) b += block_of(g.gain);
  for (const auto* rows : {&d.x_nom, &d.u_nom, &d.K}) {
    b += block_of(*rows);
    for (const auto& r : *rows) b += block_of(r);
  }
  b += block_of(d.sets);
  for (const StepSet& s : d.sets) b += block_of(s.lo) + block_of(s.hi) + block_of(s.c) + block_of(s.S) + block_of(s.tol);
  b += block_of(d.enclosures);
  for (const PeriodEnclosure& e : d.enclosures)
    b += block_of(e.state.lo) + block_of(e.state.hi) + block_of(e.workspace.lo) + block_of(e.workspace.hi);
  b += block(d.sets.size() * sizeof(std::vector<double>));  // least_norm_'s rows
  for (std::size_t k = 0; k < d.sets.size(); ++k) b += block_of(c.least_norm(static_cast<int>(k)));
  return b;
}

double kept_bytes_bound(int n, int m, int horizon, int parts, int set_generators) {
  const double T = std::max(1, horizon), sets = T + 1, g = std::max(n, set_generators);
  const long w = std::max(n, 3);
  const double row = sizeof(std::vector<double>);
  // The strings, eps, w (twice: the bound's own copy), U and the periodic flags; no W growth.
  const double fixed = block(sizeof(FunnelController)) + 2 * block(64) + 5 * doubles(std::max(n, m)) + block(n);
  const double nominal = block(sets * row) + sets * doubles(n) + 2 * block(T * row) + T * (doubles(m) + doubles(m * n));
  const double step_sets = block(sets * sizeof(StepSet)) +
                           sets * (4 * doubles(n) + 2 * doubles(static_cast<long>(n * g)));
  const double enclosures = block(T * parts * sizeof(PeriodEnclosure)) + T * parts * (2 * doubles(n) + 2 * doubles(w));
  return fixed + nominal + step_sets + enclosures + block(sets * row);
}

FunnelController::FunnelController(FunnelData d) : data_(std::move(d)) {
  least_norm_.resize(data_.sets.size());
  for (std::size_t k = 0; k < data_.sets.size(); ++k) {
    const StepSet& s = data_.sets[k];
    if (s.kind == kZonotope && s.generators <= kMaxMembershipGenerators &&
        s.S.size() == static_cast<std::size_t>(s.generators) * data_.n)
      least_norm_[k] = least_norm_map(s.S.data(), data_.n, s.generators);
  }
}

const double* FunnelController::lifted(const double* x, int k, double* buf) const {
  if (data_.periodic.empty()) return x;
  const auto& xk = data_.x_nom[static_cast<std::size_t>(k)];
  for (int j = 0; j < data_.n; ++j) buf[j] = data_.periodic[static_cast<std::size_t>(j)] ? lift_angle(x[j], xk[static_cast<std::size_t>(j)]) : x[j];
  return buf;
}

bool FunnelController::in_set(const double* x_read, int k) const {
  if (k < 0 || k > horizon()) return false;
  double buf[64];
  return in_lifted_set(lifted(x_read, k, buf), k);
}

bool FunnelController::in_lifted_set(const double* x, int k) const {
  const StepSet& s = data_.sets[static_cast<std::size_t>(k)];
  const int n = data_.n;
  for (int j = 0; j < n; ++j)
    if (!(x[j] >= s.lo[j] && x[j] <= s.hi[j])) return false;  // also refuses NaN
  if (s.kind == kBox) return true;
  if (s.kind == kZonotope) {
    // Two proposals of coefficients, the least-norm ones (cheap) and then the simplex's; only the
    // residual check decides.
    const int p = s.generators;
    double d[64], xi[kMaxMembershipGenerators];
    for (int j = 0; j < n; ++j) d[j] = x[j] - s.c[j];
    auto accepted = [&] {
      // The residual allowance holds for coefficients in the cube only: check them too.
      for (int j = 0; j < p; ++j)
        if (!(std::fabs(xi[j]) <= 1.0)) return false;
      for (int i = 0; i < n; ++i) {
        double r = -d[i];
        for (int j = 0; j < p; ++j) r += s.S[static_cast<std::size_t>(j) * n + i] * xi[j];
        if (!(std::fabs(r) <= s.tol[i])) return false;
      }
      return true;
    };
    const std::vector<double>& P = least_norm_[static_cast<std::size_t>(k)];
    if (!P.empty()) {
      least_norm_coefficients(P.data(), n, p, d, xi);
      if (accepted()) return true;
    }
    zonotope_coefficients(s.S.data(), n, p, d, xi);
    return accepted();
  }
  // The verification bounds the rounding of exactly this loop (docs/soundness.md section 11).
  for (int i = 0; i < n; ++i) {
    double y = 0.0;
    for (int j = 0; j < n; ++j) y += s.S[static_cast<std::size_t>(i) * n + j] * (x[j] - s.c[j]);
    if (!(std::fabs(y) <= 1.0)) return false;
  }
  return true;
}

ControlStatus FunnelController::input(const double* x_read, int k, double* u) const {
  if (k < 0 || k >= horizon()) return ControlStatus::OutsideHorizon;
  double buf[64];
  const double* x = lifted(x_read, k, buf);
  if (!in_lifted_set(x, k)) return ControlStatus::OutsideDomain;
  const int n = data_.n, m = data_.m;
  const auto& xk = data_.x_nom[static_cast<std::size_t>(k)];
  const auto& uk = data_.u_nom[static_cast<std::size_t>(k)];
  const auto& K = data_.K[static_cast<std::size_t>(k)];
  for (int i = 0; i < m; ++i) {
    double acc = uk[i];
    for (int j = 0; j < n; ++j) acc += K[static_cast<std::size_t>(i) * n + j] * (x[j] - xk[j]);
    u[i] = std::clamp(acc, data_.u_lo[i], data_.u_hi[i]);
  }
  return ControlStatus::Ok;
}

std::string serialize(const FunnelData& d) {
  binary::Writer p;
  p.str(d.dynamics_type);
  p.str(d.agent);
  p.u32(static_cast<std::uint32_t>(d.n));
  p.u32(static_cast<std::uint32_t>(d.m));
  p.u32(static_cast<std::uint32_t>(d.horizon()));
  p.f64(d.tau);
  p.reals(d.eps);
  p.reals(d.w);
  p.reals(d.u_lo);
  p.reals(d.u_hi);
  for (int k = 0; k <= d.horizon(); ++k) {
    const StepSet& s = d.sets[static_cast<std::size_t>(k)];
    p.reals(d.x_nom[static_cast<std::size_t>(k)]);
    p.reals(s.lo);
    p.reals(s.hi);
    p.u8(s.kind);
    if (s.kind == kZonotope) p.u32(static_cast<std::uint32_t>(s.generators));
    if (s.kind != kBox) {
      p.reals(s.c);
      p.reals(s.S);
    }
    if (s.kind == kZonotope) p.reals(s.tol);
  }
  for (int k = 0; k < d.horizon(); ++k) {
    p.reals(d.u_nom[static_cast<std::size_t>(k)]);
    p.reals(d.K[static_cast<std::size_t>(k)]);
  }
  binary::write_period_enclosures(p, d.enclosures, d.n);
  p.u32(static_cast<std::uint32_t>(d.invariant_from));
  // Format 3: the periodic coordinates, one u8 each.
  for (int i = 0; i < d.n; ++i) p.u8(i < static_cast<int>(d.periodic.size()) ? d.periodic[static_cast<std::size_t>(i)] : 0);
  return binary::envelope(kMagic, kFormatVersion, p.bytes());
}

FunnelData deserialize(const std::string& s, const std::string& what) {
  const std::string where = "controller file " + what;
  std::size_t begin = 0, end = 0;
  const std::uint32_t version = binary::open_envelope(s, kMagic, where, "a marsyn funnel controller", begin, end);
  binary::Reader r(s, begin, end, where);
  if (version < 1 || version > kFormatVersion)
    r.fail("format version " + std::to_string(version) + ", this reader understands 1 to " + std::to_string(kFormatVersion));
  FunnelData d;
  d.dynamics_type = r.str();
  d.agent = r.str();
  const std::uint32_t n = r.u32(), m = r.u32(), T = r.u32();
  if (n < 1 || n > kMaxDim || m < 1 || m > kMaxDim) r.fail("dimensions out of range");
  if (T < 1 || T > kMaxSteps) r.fail("horizon out of range");
  d.n = static_cast<int>(n);
  d.m = static_cast<int>(m);
  d.tau = r.f64();
  if (!(d.tau > 0) || !std::isfinite(d.tau)) r.fail("tau must be positive");
  d.eps = r.reals(n);
  d.w = r.reals(n);
  d.dist = DisturbanceBound(d.w);
  d.u_lo = r.reals(m);
  d.u_hi = r.reals(m);
  auto finite_all = [](const std::vector<double>& v) {
    for (double x : v)
      if (!std::isfinite(x)) return false;
    return true;
  };
  for (std::uint32_t j = 0; j < m; ++j)
    if (!(d.u_lo[j] <= d.u_hi[j])) r.fail("input bounds with lo > hi");
  for (std::uint32_t k = 0; k <= T; ++k) {
    StepSet st;
    d.x_nom.push_back(r.reals(n));
    st.lo = r.reals(n);
    st.hi = r.reals(n);
    st.kind = r.u8();
    if (st.kind > kZonotope) r.fail("unknown set kind " + std::to_string(st.kind) + " at step " + std::to_string(k));
    if (st.kind == kZonotope) {
      if (n > static_cast<std::uint32_t>(kMaxMembershipRows)) r.fail("zonotope set with more than 32 states");
      const std::uint32_t p = r.u32();
      if (p > static_cast<std::uint32_t>(kMaxMembershipGenerators)) r.fail("too many generators at step " + std::to_string(k));
      st.generators = static_cast<int>(p);
    }
    if (st.kind != kBox) {
      st.c = r.reals(n);
      st.S = r.reals(static_cast<std::size_t>(n) * (st.kind == kZonotope ? st.generators : n));
    }
    if (st.kind == kZonotope) st.tol = r.reals(n);
    bool ok = finite_all(d.x_nom.back()) && finite_all(st.c) && finite_all(st.S) && finite_all(st.tol);
    for (std::uint32_t i = 0; i < n; ++i) ok = ok && st.lo[i] <= st.hi[i];
    for (double t : st.tol) ok = ok && t >= 0;
    if (!ok) r.fail("step " + std::to_string(k) + ": non-finite or inverted set data");
    d.sets.push_back(std::move(st));
  }
  for (std::uint32_t k = 0; k < T; ++k) {
    d.u_nom.push_back(r.reals(m));
    d.K.push_back(r.reals(static_cast<std::size_t>(m) * n));
    if (!finite_all(d.u_nom.back()) || !finite_all(d.K.back())) r.fail("step " + std::to_string(k) + ": non-finite gains");
  }
  d.enclosures = binary::read_period_enclosures(r, d.n, static_cast<int>(T));
  d.invariant_from = static_cast<int>(T) + 1;
  if (version >= 2) {
    const std::uint32_t from = r.u32();
    if (from > T + 1) r.fail("invariant_from " + std::to_string(from) + " beyond the horizon " + std::to_string(T));
    d.invariant_from = static_cast<int>(from);
  }
  if (version >= 3) {
    std::vector<std::uint8_t> flags(static_cast<std::size_t>(d.n));
    for (auto& f : flags)
      if ((f = r.u8()) > 1) r.fail("bad periodic flag");
    if (std::find(flags.begin(), flags.end(), 1) != flags.end()) d.periodic = flags;
  }
  if (!r.done()) r.fail("trailing bytes in the payload");
  return d;
}

void FunnelController::write(const std::string& path) const {
  const std::string bytes = serialize(data_);
  std::ofstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot open " + path + " for writing");
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!f) throw std::runtime_error("cannot write " + path);
}

std::shared_ptr<const FunnelController> read_controller(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot open controller file " + path);
  std::ostringstream s;
  s << f.rdbuf();
  return std::make_shared<FunnelController>(deserialize(s.str(), path));
}

}  // namespace marsyn::funnel
