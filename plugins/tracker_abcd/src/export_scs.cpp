// `marsyn export --format scs`: SCOTS v0.2's text controller (a StaticController as SCOTS'
// write_to_file writes it: the state grid, the input grid, the winning domain as "state input"
// lines), line for line, so that SCOTS' reader and dtControl's fixed-position parser both read it.
// Field by field in docs/deploy.md.
//
// A time-indexed controller becomes a static one over the state extended by the step index k
// (one more, last, coordinate with eta 1 and grid points 0..T-1), as GAMARA does. The state grid
// is the bounding box of the tubes of steps 0..T-1; SCOTS' grid points are marsyn's cell centres.
// SCOTS numbers grid points and inputs with the FIRST coordinate fastest (marsyn's tables and input
// indices run the last coordinate fastest); the indices are converted here.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include "export_formats.hpp"

namespace marsyn::abcd {
namespace {

namespace fs = std::filesystem;

void vector_block(std::ostream& o, const char* name, const std::vector<double>& v) {
  o << "#VECTOR:" << name << "\n#BEGIN:" << v.size() << "\n";
  for (double x : v) o << x << "\n";
  o << "#END\n";
}

void grid_block(std::ostream& o, const char* text, const std::vector<double>& eta, const std::vector<double>& lower_left,
                const std::vector<double>& upper_right) {
  o << "#SCOTS:" << text << "\n#TYPE:UNIFORMGRID\n#MEMBER:DIM\n" << eta.size() << "\n";
  vector_block(o, "ETA", eta);
  vector_block(o, "LOWER_LEFT", lower_left);
  vector_block(o, "UPPER_RIGHT", upper_right);
}

}  // namespace

ExportResult export_scs(const GridController& ctrl, const ExportRequest& req) {
  ExportResult r;
  const ControllerData& d = ctrl.data();
  const std::string stem = req.prefix.empty() ? default_prefix(d.agent) : req.prefix;
  if (!is_c_identifier(stem)) {
    r.message = "prefix '" + stem + "' is not a C identifier ([A-Za-z_][A-Za-z0-9_]*)";
    return r;
  }
  const int n = d.n, m = d.m, steps = d.tables();
  const bool timed = !d.time_invariant;
  // Bounding box of the steps with inputs.
  std::int64_t lo[kMaxDim], hi[kMaxDim];
  for (int i = 0; i < n; ++i) {
    lo[i] = std::numeric_limits<std::int64_t>::max();
    hi[i] = std::numeric_limits<std::int64_t>::min();
  }
  for (int k = 0; k < steps; ++k) {
    const IndexBox& b = d.boxes[static_cast<size_t>(k)];
    if (b.empty()) continue;
    for (int i = 0; i < n; ++i) {
      lo[i] = std::min(lo[i], b.lo[i]);
      hi[i] = std::max(hi[i], b.hi[i]);
    }
  }
  if (lo[0] > hi[0])
    for (int i = 0; i < n; ++i) lo[i] = hi[i] = 0;  // no cells at all: a one-point grid

  // SCOTS' abs_type is uint32: every grid point id must fit.
  const int dims = n + (timed ? 1 : 0);
  std::vector<std::uint64_t> nn(static_cast<size_t>(dims));
  std::uint64_t total = 1;
  for (int i = 0; i < dims; ++i) {
    nn[static_cast<size_t>(i)] = total;
    const std::uint64_t count = i < n ? static_cast<std::uint64_t>(hi[i] - lo[i] + 1) : static_cast<std::uint64_t>(steps);
    if (count == 0 || total > 0xFFFFFFFFull / count) {
      r.message = "the SCOTS grid (tube bounding box x steps) has more than 2^32 - 1 points, SCOTS' abs_type";
      return r;
    }
    total *= count;
  }
  InputGrid ug(d.u_lo, d.u_hi, d.eta_u);
  std::vector<std::uint64_t> unn(static_cast<size_t>(m));
  {
    std::uint64_t t = 1;
    for (int j = 0; j < m; ++j) {
      unn[static_cast<size_t>(j)] = t;
      t *= ug.count()[static_cast<size_t>(j)];
    }
  }

  // (state id, input id) of every winning (cell, k), sorted by state id as SCOTS writes them.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  std::int64_t idx[kMaxDim];
  for (int k = 0; k < steps; ++k) {
    const IndexBox& b = d.boxes[static_cast<size_t>(k)];
    const std::int64_t cells = b.size(), off = d.offsets[static_cast<size_t>(k)];
    for (std::int64_t c = 0; c < cells; ++c) {
      const std::uint16_t j = d.inputs[static_cast<size_t>(off + c)];
      if (j == kLosing || j == kTarget) continue;
      b.unlinear(c, idx);
      std::uint64_t id = timed ? static_cast<std::uint64_t>(k) * nn[static_cast<size_t>(n)] : 0;
      for (int i = 0; i < n; ++i) id += static_cast<std::uint64_t>(idx[i] - lo[i]) * nn[static_cast<size_t>(i)];
      // marsyn: mixed radix, first input coordinate slowest; SCOTS: first fastest.
      std::uint64_t uid = 0, rest = j;
      for (int q = m - 1; q >= 0; --q) {
        const std::uint64_t cq = ug.count()[static_cast<size_t>(q)];
        uid += (rest % cq) * unn[static_cast<size_t>(q)];
        rest /= cq;
      }
      pairs.emplace_back(static_cast<std::uint32_t>(id), static_cast<std::uint32_t>(uid));
    }
  }
  std::sort(pairs.begin(), pairs.end());

  std::vector<double> eta(d.eta_x), ll(static_cast<size_t>(n)), ur(static_cast<size_t>(n));
  bool aligned = true;
  for (int i = 0; i < n; ++i) {
    const size_t s = static_cast<size_t>(i);
    ll[s] = d.origin[s] + (static_cast<double>(lo[i]) + 0.5) * d.eta_x[s];  // centre of the first cell
    ur[s] = ll[s] + d.eta_x[s] * static_cast<double>(hi[i] - lo[i]);     // as SCOTS' get_upper_right
    const double q = ll[s] / d.eta_x[s];
    if (std::abs(q - std::round(q)) > 1e-6) aligned = false;
  }
  if (timed) {
    eta.push_back(1.0);
    ll.push_back(0.0);
    ur.push_back(static_cast<double>(steps - 1));
  }
  std::vector<double> ueta(d.eta_u), ull(d.u_lo), uur(static_cast<size_t>(m));
  for (int j = 0; j < m; ++j)
    uur[static_cast<size_t>(j)] = d.u_lo[static_cast<size_t>(j)] +
                                  d.eta_u[static_cast<size_t>(j)] * static_cast<double>(ug.count()[static_cast<size_t>(j)] - 1);

  std::ostringstream o;
  o << std::setprecision(std::numeric_limits<double>::max_digits10);
  o << "#SCOTS:v0.2\n#TYPE:STATICCONTROLLER\n";
  grid_block(o, "STATE_SPACE", eta, ll, ur);
  grid_block(o, "INPUT_SPACE", ueta, ull, uur);
  o << "#TYPE:WINNINGDOMAIN\n#SCOTS:i (state) j_0 ... j_n (valid inputs)\n#MATRIX:DATA\n#BEGIN:" << total << " 1\n";
  for (const auto& [i, j] : pairs) o << i << " " << j << "\n";
  o << "#END\n";

  try {
    const fs::path dir(req.out_dir.empty() ? "." : req.out_dir);
    fs::create_directories(dir);
    const fs::path file = dir / (stem + ".scs");
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot open " + file.string() + " for writing");
    out << o.str();
    if (!out) throw std::runtime_error("write to " + file.string() + " failed");
    r.files = {file.string()};
  } catch (const std::exception& e) {
    r.message = e.what();
    return r;
  }
  r.ok = true;
  r.entries = static_cast<long long>(pairs.size());
  std::ostringstream msg;
  msg << "agent " << d.agent << ": " << pairs.size() << " (cell" << (timed ? ", k" : "") << ") -> input pairs over a "
      << dims << "-dimensional SCOTS grid of " << total << " points";
  if (!aligned)
    msg << "; note: the cell centres are not integer multiples of eta, and SCOTS' own read_from_file re-aligns grids "
           "to them (dtControl reads the values as written; docs/deploy.md)";
  r.message = msg.str();
  return r;
}

}  // namespace marsyn::abcd
