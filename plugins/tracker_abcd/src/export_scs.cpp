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

// The bounding box of the steps with inputs; a one-point grid when there are no cells at all.
void bounding_box(const ControllerData& d, std::int64_t* lo, std::int64_t* hi) {
  const int n = d.n;
  for (int i = 0; i < n; ++i) {
    lo[i] = std::numeric_limits<std::int64_t>::max();
    hi[i] = std::numeric_limits<std::int64_t>::min();
  }
  for (int k = 0; k < d.tables(); ++k) {
    const IndexBox& b = d.boxes[static_cast<size_t>(k)];
    if (b.empty()) continue;
    for (int i = 0; i < n; ++i) {
      lo[i] = std::min(lo[i], b.lo[i]);
      hi[i] = std::max(hi[i], b.hi[i]);
    }
  }
  if (lo[0] > hi[0])
    for (int i = 0; i < n; ++i) lo[i] = hi[i] = 0;
}

// SCOTS' strides of the state grid (first coordinate fastest, the step last when timed) into
// nn, its number of points into total; false when an id would not fit SCOTS' abs_type, uint32.
bool state_strides(const ControllerData& d, const std::int64_t* lo, const std::int64_t* hi, int dims,
                   std::vector<std::uint64_t>& nn, std::uint64_t& total) {
  nn.assign(static_cast<size_t>(dims), 0);
  total = 1;
  for (int i = 0; i < dims; ++i) {
    nn[static_cast<size_t>(i)] = total;
    const std::uint64_t count = i < d.n ? static_cast<std::uint64_t>(hi[i] - lo[i] + 1) : static_cast<std::uint64_t>(d.tables());
    if (count == 0 || total > 0xFFFFFFFFull / count) return false;
    total *= count;
  }
  return true;
}

// (state id, input id) of every winning (cell, k), sorted by state id as SCOTS writes them.
std::vector<std::pair<std::uint32_t, std::uint32_t>> winning_pairs(const ControllerData& d, const InputGrid& ug,
                                                                   const std::int64_t* lo,
                                                                   const std::vector<std::uint64_t>& nn) {
  const int n = d.n, m = d.m;
  const bool timed = !d.time_invariant;
  std::vector<std::uint64_t> unn(static_cast<size_t>(m));
  {
    std::uint64_t t = 1;
    for (int j = 0; j < m; ++j) {
      unn[static_cast<size_t>(j)] = t;
      t *= ug.count()[static_cast<size_t>(j)];
    }
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  std::int64_t idx[kMaxDim];
  for (int k = 0; k < d.tables(); ++k) {
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
  return pairs;
}

// The file's text: the state grid (cell centres of the bounding box, and k), the input grid and
// the winning domain. `aligned`: whether the centres are integer multiples of eta.
std::string scots_text(const ControllerData& d, const InputGrid& ug, const std::int64_t* lo, const std::int64_t* hi,
                       std::uint64_t total, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs,
                       bool& aligned) {
  const int n = d.n, m = d.m;
  std::vector<double> eta(d.eta_x), ll(static_cast<size_t>(n)), ur(static_cast<size_t>(n));
  aligned = true;
  for (int i = 0; i < n; ++i) {
    const size_t s = static_cast<size_t>(i);
    ll[s] = d.origin[s] + (static_cast<double>(lo[i]) + 0.5) * d.eta_x[s];  // centre of the first cell
    ur[s] = ll[s] + d.eta_x[s] * static_cast<double>(hi[i] - lo[i]);     // as SCOTS' get_upper_right
    const double q = ll[s] / d.eta_x[s];
    if (std::abs(q - std::round(q)) > 1e-6) aligned = false;
  }
  if (!d.time_invariant) {
    eta.push_back(1.0);
    ll.push_back(0.0);
    ur.push_back(static_cast<double>(d.tables() - 1));
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
  return o.str();
}

// Writes <dir>/<stem>.scs; its path, or throws.
std::string write_file(const std::string& out_dir, const std::string& stem, const std::string& text) {
  const fs::path dir(out_dir.empty() ? "." : out_dir);
  fs::create_directories(dir);
  const fs::path file = dir / (stem + ".scs");
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot open " + file.string() + " for writing");
  out << text;
  if (!out) throw std::runtime_error("write to " + file.string() + " failed");
  return file.string();
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
  const bool timed = !d.time_invariant;
  std::int64_t lo[kMaxDim], hi[kMaxDim];
  bounding_box(d, lo, hi);
  const int dims = d.n + (timed ? 1 : 0);
  std::vector<std::uint64_t> nn;
  std::uint64_t total = 1;
  if (!state_strides(d, lo, hi, dims, nn, total)) {
    r.message = "the SCOTS grid (tube bounding box x steps) has more than 2^32 - 1 points, SCOTS' abs_type";
    return r;
  }
  InputGrid ug(d.u_lo, d.u_hi, d.eta_u);
  const auto pairs = winning_pairs(d, ug, lo, nn);
  bool aligned = true;
  const std::string text = scots_text(d, ug, lo, hi, total, pairs, aligned);
  try {
    r.files = {write_file(req.out_dir, stem, text)};
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
