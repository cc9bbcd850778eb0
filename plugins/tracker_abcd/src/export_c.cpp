// `marsyn export --format c`: one dependency-free C99 header and source per controller, with the
// controller as const tables and one lookup function that answers exactly as GridController::input
// (docs/deploy.md).
//
// Bit-identity with the C++ lookup:
// - The quantizer is the same two IEEE operations and floor: floor((x - o) / eta), with o and eta
//   written as hexadecimal floating literals (exact).
// - The index-box test is done on the floor's double result against lo and the extent (both
//   integers far below 2^53), which is exact for every finite x and also rejects NaN and
//   infinities, as the C++ isfinite() test and the int64 box test do.
// - Inputs are not recomputed: the table holds the doubles InputGrid::value() produced, so no
//   multiply-add (and no contraction into an FMA) can change them.
// Compact tables: the distinct inputs the controller uses form a palette; each table entry is a
// palette code (plus "losing" and, in whole-domain mode, "target"), stored either bit-packed
// (dense, O(1) lookup) or as runs over the row-major cell order (rle, binary search per lookup).
// Every other table gets the smallest fixed-width integer type that holds its values.
#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>

#include "export_formats.hpp"
#include "marsyn/c_source.hpp"

namespace marsyn::abcd {
namespace {

using c_source::array_body;
using c_source::array_body_2d;
using c_source::hex_double;
using c_source::upper;

// Smallest unsigned width in bytes (1, 2, 4, 8) holding v.
int unsigned_bytes(unsigned long long v) {
  if (v <= 0xFFull) return 1;
  if (v <= 0xFFFFull) return 2;
  if (v <= 0xFFFFFFFFull) return 4;
  return 8;
}
// Smallest signed width holding [lo, hi], never the type's minimum (so that every value can be
// written as a plain decimal literal).
int signed_bytes(long long lo, long long hi) {
  if (lo > -128 && hi <= 127) return 1;
  if (lo > -32768 && hi <= 32767) return 2;
  if (lo > -2147483647ll - 1 && hi <= 2147483647ll) return 4;
  return 8;
}
std::string utype(int bytes) { return "uint" + std::to_string(8 * bytes) + "_t"; }
std::string stype(int bytes) { return "int" + std::to_string(8 * bytes) + "_t"; }

// The controller's tables in both encodings.
struct Tables {
  int n = 0, m = 0, steps = 0;  // steps: tables (T, or 1 in whole-domain mode)
  int boxes = 0;                // tube boxes: T + 1 (the monitor answers at T too), or 1
  bool time_invariant = false;
  std::vector<std::uint16_t> palette;  // input indices in use, ascending
  unsigned losing = 0, target = 0;     // codes
  bool has_target = false;
  unsigned codes = 0;  // number of distinct codes
  std::vector<unsigned> entries;       // all tables' codes, tables concatenated
  std::vector<long long> table_start;  // steps + 1 offsets into entries
  int bits = 0;                        // dense: bits per entry
  std::vector<std::uint8_t> packed;    // dense: the bit stream, little-endian, plus 3 bytes of padding
  std::vector<long long> run_end;      // rle: one past each run's last cell, local to its table
  std::vector<unsigned> run_code;
  std::vector<long long> run_start;    // rle: steps + 1 offsets into the runs
  // Widths (bytes) of the integer tables.
  int lo_w = 1, ext_w = 1, dense_off_w = 1, rle_off_w = 1, run_end_w = 1, run_code_w = 1;
  bool wide_bits = false;  // dense: bit positions need 64 bits
  long long lo_min = 0, lo_max = 0, ext_max = 0, table_max = 0;

  long long common_bytes() const {
    return 16ll * n + static_cast<long long>(std::max(1, boxes)) * n * (lo_w + ext_w) +
           static_cast<long long>(std::max<size_t>(1, palette.size())) * m * 8;
  }
  long long dense_bytes() const {
    return common_bytes() + static_cast<long long>(std::max(1, steps)) * dense_off_w + static_cast<long long>(packed.size());
  }
  long long rle_bytes() const {
    return common_bytes() + static_cast<long long>(steps + 1) * rle_off_w +
           static_cast<long long>(std::max<size_t>(1, run_end.size())) * (run_end_w + run_code_w);
  }
};

Tables build_tables(const ControllerData& d) {
  Tables t;
  t.n = d.n;
  t.m = d.m;
  t.steps = d.tables();
  t.boxes = static_cast<int>(d.boxes.size());
  t.time_invariant = d.time_invariant;
  std::vector<bool> used(65536, false);
  for (auto v : d.inputs) {
    if (v == kTarget) t.has_target = true;
    else if (v != kLosing) used[v] = true;
  }
  for (unsigned j = 0; j < 65536; ++j)
    if (used[j]) t.palette.push_back(static_cast<std::uint16_t>(j));
  std::vector<unsigned> code_of(65536, 0);
  for (size_t c = 0; c < t.palette.size(); ++c) code_of[t.palette[c]] = static_cast<unsigned>(c);
  t.losing = static_cast<unsigned>(t.palette.size());
  t.target = t.losing + 1;
  t.codes = t.losing + 1 + (t.has_target ? 1 : 0);
  code_of[kLosing] = t.losing;
  code_of[kTarget] = t.target;

  t.lo_min = std::numeric_limits<long long>::max();
  t.lo_max = std::numeric_limits<long long>::min();
  for (int k = 0; k < t.boxes; ++k) {
    const IndexBox& b = d.boxes[static_cast<size_t>(k)];
    const bool empty = b.empty();
    for (int i = 0; i < d.n; ++i) {
      t.lo_min = std::min<long long>(t.lo_min, b.lo[i]);
      t.lo_max = std::max<long long>(t.lo_max, b.lo[i]);
      t.ext_max = std::max<long long>(t.ext_max, empty ? 0 : b.extent(i));
    }
    if (k < t.steps) t.table_max = std::max<long long>(t.table_max, b.size());
  }
  if (t.boxes == 0) t.lo_min = t.lo_max = 0;

  t.table_start.push_back(0);
  t.run_start.push_back(0);
  for (int k = 0; k < t.steps; ++k) {
    const std::int64_t cells = d.boxes[static_cast<size_t>(k)].size();
    const std::int64_t off = d.offsets[static_cast<size_t>(k)];
    for (std::int64_t c = 0; c < cells; ++c) {
      const unsigned code = code_of[d.inputs[static_cast<size_t>(off + c)]];
      t.entries.push_back(code);
      if (c == 0 || code != t.run_code.back()) {
        if (c > 0) t.run_end.push_back(c);
        t.run_code.push_back(code);
      }
    }
    if (cells > 0) t.run_end.push_back(cells);
    t.table_start.push_back(static_cast<long long>(t.entries.size()));
    t.run_start.push_back(static_cast<long long>(t.run_end.size()));
  }

  while ((1u << t.bits) < t.codes) ++t.bits;
  const unsigned long long total_bits = static_cast<unsigned long long>(t.entries.size()) * static_cast<unsigned>(t.bits);
  t.packed.assign(static_cast<size_t>((total_bits + 7) / 8 + 3), 0);
  if (t.bits > 0)
    for (size_t e = 0; e < t.entries.size(); ++e) {
      const unsigned long long bit = e * static_cast<unsigned long long>(t.bits);
      for (int b = 0; b < t.bits; ++b)
        if ((t.entries[e] >> b) & 1u) t.packed[static_cast<size_t>((bit + b) >> 3)] |= static_cast<std::uint8_t>(1u << ((bit + b) & 7));
    }
  t.wide_bits = total_bits + 32 > 0xFFFFFFFFull;
  t.lo_w = signed_bytes(t.lo_min, t.lo_max);
  t.ext_w = unsigned_bytes(static_cast<unsigned long long>(t.ext_max));
  t.dense_off_w = unsigned_bytes(static_cast<unsigned long long>(t.entries.size()));
  t.rle_off_w = unsigned_bytes(static_cast<unsigned long long>(t.run_end.size()));
  t.run_end_w = unsigned_bytes(static_cast<unsigned long long>(t.table_max));
  t.run_code_w = unsigned_bytes(t.codes);
  return t;
}

std::string header_text(const ControllerData& d, const std::string& prefix, const ExportRequest& req) {
  const std::string P = upper(prefix);
  c_source::CHeader h;
  h.prefix = prefix;
  h.n = d.n;
  h.m = d.m;
  h.horizon = d.time_invariant ? -1 : d.tables();
  h.tau = d.tau;
  h.about = prefix + ".h: controller of agent '" + d.agent + "' (" + d.dynamics_type + "), generated by `marsyn export`" +
            (req.source.empty() ? "" : " from " + req.source) + ".\n * Dependency-free C99 (docs/deploy.md). " + prefix +
            "_input(x, k, u) answers exactly as marsyn's\n * Controller::input: " + P + "_OK with the verified input in u[0.." +
            std::to_string(d.m - 1) + "], " + P + "_OUTSIDE_DOMAIN when x's\n * cell is not winning at step k (or x is not finite), " +
            P + "_OUTSIDE_HORIZON for k outside\n * the tables" +
            (d.time_invariant ? " (whole-domain controller: k is ignored) or when the target is reached"
                              : " (0 <= k < " + std::to_string(d.tables()) + ")") +
            ". " + prefix + "_inside(x, k) is GridController::winning:\n * x's cell is winning at k" +
            (d.time_invariant ? " or in the target" : ", or in the tube at k = T") + ". No allocation, no state.";
  return c_source::header_text(h);
}

// The grid, the tubes' boxes and the inputs in use as const arrays, and the LOSING/TARGET codes.
void grid_arrays(std::ostringstream& c, const ControllerData& d, const Tables& t, const std::string& p,
                 const std::string& P) {
  const int B = std::max(1, t.boxes);
  c << "/* grid origin and cell size per state coordinate (exact hexadecimal literals) */\n";
  c << "static const double " << p << "origin[" << d.n << "] = ";
  array_body(c, d.n, [&](long long i) { return hex_double(d.origin[static_cast<size_t>(i)]); });
  c << ";\nstatic const double " << p << "eta[" << d.n << "] = ";
  array_body(c, d.n, [&](long long i) { return hex_double(d.eta_x[static_cast<size_t>(i)]); });
  c << ";\n\n/* per step k = 0..T: the tube's first cell index and its extent per coordinate (row-major, last fastest) */\n";
  c << "static const " << stype(t.lo_w) << " " << p << "lo[" << B << "][" << d.n << "] = ";
  array_body_2d(c, B, d.n, [&](long long i) -> std::string {
    if (t.boxes == 0) return "0";
    return std::to_string(d.boxes[static_cast<size_t>(i / d.n)].lo[i % d.n]);
  });
  c << ";\nstatic const " << utype(t.ext_w) << " " << p << "ext[" << B << "][" << d.n << "] = ";
  array_body_2d(c, B, d.n, [&](long long i) -> std::string {
    if (t.boxes == 0) return "0";
    const IndexBox& b = d.boxes[static_cast<size_t>(i / d.n)];
    return std::to_string(b.empty() ? 0 : b.extent(static_cast<int>(i % d.n)));
  });
  const size_t P_count = std::max<size_t>(1, t.palette.size());
  c << ";\n\n/* the inputs in use, as InputGrid::value decoded them (grid indices:";
  for (size_t i = 0; i < t.palette.size() && i < 64; ++i) c << " " << t.palette[i];
  if (t.palette.size() > 64) c << " ...";
  c << ") */\nstatic const double " << p << "u[" << P_count << "][" << d.m << "] = ";
  std::vector<double> uvals(P_count * static_cast<size_t>(d.m), 0.0);
  InputGrid ug(d.u_lo, d.u_hi, d.eta_u);
  for (size_t i = 0; i < t.palette.size(); ++i) ug.value(t.palette[i], &uvals[i * static_cast<size_t>(d.m)]);
  array_body_2d(c, static_cast<long long>(P_count), d.m, [&](long long i) { return hex_double(uvals[static_cast<size_t>(i)]); });
  c << ";\n\n#define " << P << "_LOSING " << t.losing << "u\n";
  if (t.has_target) c << "#define " << P << "_TARGET " << t.target << "u\n";
  c << "\n";

}

// The bit-packed tables and their code(k, l).
void dense_tables(std::ostringstream& c, const Tables& t, const std::string& p) {
  const int S = std::max(1, t.steps);
  c << "/* table k's entries start at entry off[k]; entry e holds a code in bits [" << t.bits << " e, " << t.bits
    << " e + " << t.bits << ") of bits[] */\n";
  c << "static const " << utype(t.dense_off_w) << " " << p << "off[" << S << "] = ";
  array_body(c, S, [&](long long k) { return std::to_string(t.steps == 0 ? 0 : t.table_start[static_cast<size_t>(k)]); });
  c << ";\nstatic const uint8_t " << p << "bits[" << t.packed.size() << "] = ";
  array_body(c, static_cast<long long>(t.packed.size()), [&](long long i) { return std::to_string(t.packed[static_cast<size_t>(i)]); });
  c << ";\n\nstatic unsigned " << p << "code(int k, uint32_t l)\n{\n";
  if (t.bits == 0) {
    c << "  (void)k;\n  (void)l;\n  return 0u;\n}\n\n";
  } else {
    const std::string pos = t.wide_bits ? "uint64_t" : "uint32_t";
    c << "  const " << pos << " bit = ((" << pos << ")" << p << "off[k] + l) * " << t.bits << "u;\n"
      << "  const uint8_t *b = " << p << "bits + (bit >> 3);\n"
      << "  const uint32_t w = (uint32_t)b[0] | ((uint32_t)b[1] << 8) | ((uint32_t)b[2] << 16);\n"
      << "  return (unsigned)((w >> (unsigned)(bit & 7u)) & " << ((1u << t.bits) - 1) << "u);\n}\n\n";
  }
}

// The run-length tables and their code(k, l), a binary search over the table's runs.
void rle_tables(std::ostringstream& c, const Tables& t, const std::string& p) {
  c << "/* table k's runs are runs [start[k], start[k+1]); a run covers cells up to end (exclusive, local to its table) */\n";
  c << "static const " << utype(t.rle_off_w) << " " << p << "start[" << t.steps + 1 << "] = ";
  array_body(c, t.steps + 1, [&](long long k) { return std::to_string(t.run_start[static_cast<size_t>(k)]); });
  const long long R = std::max<long long>(1, static_cast<long long>(t.run_end.size()));
  c << ";\nstatic const " << utype(t.run_end_w) << " " << p << "end[" << R << "] = ";
  array_body(c, static_cast<long long>(t.run_end.size()), [&](long long i) { return std::to_string(t.run_end[static_cast<size_t>(i)]); });
  c << ";\nstatic const " << utype(t.run_code_w) << " " << p << "code_of_run[" << R << "] = ";
  array_body(c, static_cast<long long>(t.run_code.size()), [&](long long i) { return std::to_string(t.run_code[static_cast<size_t>(i)]); });
  c << ";\n\nstatic unsigned " << p << "code(int k, uint32_t l)\n{\n"
    << "  uint32_t a = (uint32_t)" << p << "start[k], b = (uint32_t)" << p << "start[k + 1];\n"
    << "  while (a < b) {\n"
    << "    const uint32_t mid = a + (b - a) / 2u;\n"
    << "    if ((uint32_t)" << p << "end[mid] <= l)\n      a = mid + 1u;\n    else\n      b = mid;\n  }\n"
    << "  return (unsigned)" << p << "code_of_run[a];\n}\n\n";
}

// A controller with periodic coordinates reads an angle on any branch: the table of the steps'
// references and the lift, the same two operations and remainder as marsyn::lift_angle.
// The coordinates the controller lifts (none for a whole-domain controller).
std::vector<int> periodic_columns(const GridController& ctrl) {
  std::vector<int> periodic;
  for (int i = 0; i < ctrl.data().n; ++i)
    if (ctrl.any_periodic() && ctrl.data().is_periodic(i)) periodic.push_back(i);
  return periodic;
}

std::vector<int> lift_code(std::ostringstream& c, const GridController& ctrl, const std::string& p) {
  const ControllerData& d = ctrl.data();
  const std::vector<int> periodic = periodic_columns(ctrl);
  if (periodic.empty()) return periodic;
  const long long B = static_cast<long long>(d.boxes.size()), NP = static_cast<long long>(periodic.size());
  c << "/* periodic coordinates (angles):";
  for (int i : periodic) c << " " << i;
  c << "; per step k = 0..T the reference each is read against (the tube box's centre) */\n";
  c << "static const double " << p << "ref[" << B << "][" << NP << "] = ";
  array_body_2d(c, B, NP, [&](long long e) { return hex_double(ctrl.reference(static_cast<int>(e / NP), periodic[static_cast<size_t>(e % NP)])); });
  c << ";\n\n";
  c_source::lift_function(c, p);
  return periodic;
}

// locate, <prefix>_input and <prefix>_inside.
void lookup_functions(std::ostringstream& c, const ControllerData& d, const Tables& t, const std::string& prefix,
                      const std::vector<int>& periodic) {
  const std::string p = prefix + "_", P = upper(prefix);
  // One quantizer for the lookup and the monitor: x's cell as an index l into table k.
  c << "static int " << p << "locate(const double *x_read, int k, uint32_t *l)\n{\n  int i;\n";
  if (periodic.empty()) {
    c << "  const double *x = x_read;\n";
  } else {
    c << "  double x[" << d.n << "];\n  for (i = 0; i < " << d.n << "; ++i)\n    x[i] = x_read[i];\n";
    for (size_t j = 0; j < periodic.size(); ++j)
      c << "  x[" << periodic[j] << "] = " << p << "lift(x_read[" << periodic[j] << "], " << p << "ref[k][" << j << "]);\n";
  }
  c << "  *l = 0;\n"
    << "  for (i = 0; i < " << d.n << "; ++i) {\n"
    << "    const double q = floor((x[i] - " << p << "origin[i]) / " << p << "eta[i]);\n"
    << "    const double r = q - (double)" << p << "lo[k][i];\n"
    << "    if (!(r >= 0.0 && r < (double)" << p << "ext[k][i]))\n      return 0;\n"
    << "    *l = *l * (uint32_t)" << p << "ext[k][i] + (uint32_t)r;\n  }\n  return 1;\n}\n\n";
  c << "int " << prefix << "_input(const double *x, int k, double *u)\n{\n"
    << "  uint32_t l;\n  unsigned code;\n  int i;\n";
  if (d.time_invariant) c << "  k = 0;\n";
  c << "  if (k < 0 || k >= " << t.steps << ")\n    return " << P << "_OUTSIDE_HORIZON;\n"
    << "  if (!" << p << "locate(x, k, &l))\n    return " << P << "_OUTSIDE_DOMAIN;\n"
    << "  code = " << p << "code(k, l);\n"
    << "  if (code == " << P << "_LOSING)\n    return " << P << "_OUTSIDE_DOMAIN;\n";
  if (t.has_target) c << "  if (code == " << P << "_TARGET)\n    return " << P << "_OUTSIDE_HORIZON;\n";
  c << "  for (i = 0; i < " << d.m << "; ++i)\n    u[i] = " << p << "u[code][i];\n"
    << "  return " << P << "_OK;\n}\n\n";
  c << "int " << prefix << "_inside(const double *x, int k)\n{\n  uint32_t l;\n";
  if (d.time_invariant) c << "  k = 0;\n";
  c << "  if (k < 0 || k >= " << t.boxes << " || !" << p << "locate(x, k, &l))\n    return 0;\n";
  if (t.boxes > t.steps) c << "  if (k >= " << t.steps << ")\n    return 1; /* step T: the tube, no table */\n";
  c << "  return " << p << "code(k, l) != " << P << "_LOSING;\n}\n";
}

std::string source_text(const GridController& ctrl, const Tables& t, const std::string& prefix, bool rle,
                        const ExportRequest& req) {
  const ControllerData& d = ctrl.data();
  const std::string p = prefix + "_", P = upper(prefix);
  std::ostringstream c;
  c << "/* " << prefix << ".c: controller of agent '" << d.agent << "', generated by `marsyn export`"
    << (req.source.empty() ? "" : " from " + req.source) << ".\n"
    << " * " << t.steps << (d.time_invariant ? " table (whole-domain)" : " steps") << ", " << t.entries.size()
    << " table entries, " << t.palette.size() << " distinct inputs; encoding: "
    << (rle ? "runs (" + std::to_string(t.run_end.size()) + ")" : "bit-packed (" + std::to_string(t.bits) + " bits per entry)")
    << "; const data " << (rle ? t.rle_bytes() : t.dense_bytes()) << " bytes. */\n"
    << c_source::source_preamble(prefix, false);
  grid_arrays(c, d, t, p, P);
  if (!rle) dense_tables(c, t, p);
  else rle_tables(c, t, p);
  const std::vector<int> periodic = lift_code(c, ctrl, p);
  lookup_functions(c, d, t, prefix, periodic);
  return c.str();
}

}  // namespace

CTableSizes c_table_sizes(const ControllerData& d) {
  const Tables t = build_tables(d);
  CTableSizes s;
  s.dense = t.dense_bytes();
  s.rle = t.rle_bytes();
  s.entries = static_cast<long long>(t.entries.size());
  s.runs = static_cast<long long>(t.run_end.size());
  s.palette = static_cast<long long>(t.palette.size());
  s.bits = t.bits;
  return s;
}

ExportResult export_c(const GridController& ctrl, const ExportRequest& req) {
  ExportResult r;
  const ControllerData& d = ctrl.data();
  std::string prefix;
  if (!c_source::c_request_prefix(req, d.agent, prefix, r)) return r;
  const Tables t = build_tables(d);
  if (t.table_max > 0xFFFFFFFFll) {
    r.message = "a step's tube has more than 2^32 cells; the C lookup indexes tables with 32 bits";
    return r;
  }
  const bool rle = req.encoding == "rle" || (req.encoding == "auto" && t.rle_bytes() < t.dense_bytes());  // the ref table is in both
  if (!c_source::write_header_and_source(req, prefix, header_text(d, prefix, req), source_text(ctrl, t, prefix, rle, req), r))
    return r;
  r.ok = true;
  r.encoding = rle ? "rle" : "dense";
  // The periodic coordinates' reference table (lift_code), in either encoding.
  const long long ref_bytes = static_cast<long long>(periodic_columns(ctrl).size() * d.boxes.size()) * 8;
  r.dense_bytes = t.dense_bytes() + ref_bytes;
  r.rle_bytes = t.rle_bytes() + ref_bytes;
  r.const_data_bytes = rle ? r.rle_bytes : r.dense_bytes;
  r.entries = static_cast<long long>(t.entries.size());
  std::ostringstream m;
  m << "agent " << d.agent << ": " << t.entries.size() << " table entries, " << t.palette.size() << " distinct inputs, "
    << r.encoding << " tables, const data " << r.const_data_bytes << " bytes (dense " << r.dense_bytes << ", rle "
    << r.rle_bytes << ")";
  r.message = m.str();
  return r;
}

ExportResult GridController::export_to(const ExportRequest& request) const {
  if (request.format == "c") return export_c(*this, request);
  if (request.format == "scs") return export_scs(*this, request);
  ExportResult r;
  r.message = "unknown export format '" + request.format + "'; expected c or scs";
  return r;
}

}  // namespace marsyn::abcd
