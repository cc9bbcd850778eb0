#pragma once
// Writing a controller as dependency-free C99 (`marsyn export --format c`, docs/deploy.md): the
// pieces every tracker's generator shares, so that all exported controllers have one header
// layout (dimensions, status codes, `<prefix>_input` and the runtime monitor `<prefix>_inside`)
// and write their constants the same exact way. Header-only, for tracker plugins.
#include <cctype>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "marsyn/controller_export.hpp"
#include "marsyn/number_text.hpp"
#include "marsyn/periodic.hpp"

namespace marsyn::c_source {

// [A-Za-z_][A-Za-z0-9_]*: what a C symbol prefix must be.
inline bool is_c_identifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char ch : s)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_')) return false;
  return true;
}

// The agent's name made into a C identifier (other characters become '_', a leading digit gets
// "c_" in front): the default prefix.
inline std::string default_prefix(const std::string& agent) {
  std::string s = agent.empty() ? "controller" : agent;
  for (auto& ch : s)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_') || static_cast<unsigned char>(ch) > 127) ch = '_';
  if (std::isdigit(static_cast<unsigned char>(s[0]))) s = "c_" + s;
  return s;
}

// A hexadecimal floating literal: C99 reads it back as the very same double.
using marsyn::hex_double;

inline std::string upper(std::string s) {
  for (auto& ch : s) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  return s;
}

// "{a, b, ...}" with line breaks; C99 has no empty arrays, so count 0 writes "{0}".
template <class F>
void array_body(std::ostream& o, long long count, F value) {
  o << "{";
  if (count == 0) {
    o << "0}";
    return;
  }
  for (long long i = 0; i < count; ++i) o << (i % 16 == 0 ? "\n  " : " ") << value(i) << (i + 1 < count ? "," : "");
  o << "\n}";
}

// "{{..}, {..}}", one row per line (rows, cols >= 1).
template <class F>
void array_body_2d(std::ostream& o, long long rows, long long cols, F value) {
  o << "{";
  for (long long r = 0; r < rows; ++r) {
    o << "\n  {";
    for (long long c = 0; c < cols; ++c) o << (c ? ", " : "") << value(r * cols + c);
    o << "}" << (r + 1 < rows ? "," : "");
  }
  o << "\n}";
}

// What one exported controller declares; `about` is the header's opening comment (without the
// comment markers' first and last line), `horizon` is T (-1: time-invariant).
// invariant_from: the first step from which every verified set is invariant (horizon + 1: none).
struct CHeader {
  std::string prefix, about;
  int n = 0, m = 0, horizon = 0;
  double tau = 0.0;
  int invariant_from = 0;
};

inline std::string header_text(const CHeader& h) {
  const std::string P = upper(h.prefix);
  std::ostringstream o;
  o << "/* " << h.about << " */\n"
    << "#ifndef " << P << "_H_\n#define " << P << "_H_\n\n"
    << "#ifdef __cplusplus\nextern \"C\" {\n#endif\n\n"
    << "#define " << P << "_STATE_DIM " << h.n << "\n"
    << "#define " << P << "_INPUT_DIM " << h.m << "\n"
    << "#define " << P << "_HORIZON " << h.horizon << "  /* -1: time-invariant */\n"
    << "#define " << P << "_TAU " << hex_double(h.tau) << "  /* sampling period [s], " << h.tau << " */\n\n"
    << "#define " << P << "_OK 0\n#define " << P << "_OUTSIDE_DOMAIN 1\n#define " << P << "_OUTSIDE_HORIZON 2\n\n"
    << "/* The verified input for x at step k: " << P << "_OK (u written), " << P << "_OUTSIDE_DOMAIN or " << P
    << "_OUTSIDE_HORIZON. */\n"
    << "int " << h.prefix << "_input(const double *x, int k, double *u);\n"
    << "/* Runtime monitor: 1 when x lies in the verified set V_k of step k (0 <= k <= T), else 0.\n"
    << " * From step " << P << "_INVARIANT_FROM on, a 1 means the guarantee holds from x: V_k is invariant\n"
    << " * (from every state it accepts, the closed loop reaches V_{k+1} under every disturbance in W and\n"
    << " * stays in the verified enclosures between the samples). Before that step a 1 says only that\n"
    << " * the run is consistent with what was verified from the initial set (docs/deploy.md).\n"
    << " * 0 means the robot has left what was verified (a sensor fault, a disturbance beyond W). */\n"
    << "int " << h.prefix << "_inside(const double *x, int k);\n"
    << "#define " << P << "_INVARIANT_FROM " << h.invariant_from << "  /* " << P
    << "_HORIZON + 1: no step; 0: every step */\n\n"
    << "#ifdef __cplusplus\n}\n#endif\n\n#endif /* " << P << "_H_ */\n";
  return o.str();
}

// `static double <p>lift(double v, double ref)`: an angle read on any branch moved onto the one
// nearest ref, the same two operations and remainder as marsyn::lift_angle (so C and C++ agree
// bit for bit): every tracker's source with periodic coordinates (docs/deploy.md).
inline void lift_function(std::ostream& o, const std::string& p) {
  o << "/* the angle v on the branch nearest ref: v itself within half a turn (pi), else moved by whole turns */\n"
    << "static double " << p << "lift(double v, double ref)\n{\n  const double d = v - ref;\n"
    << "  return fabs(d) <= " << hex_double(0.5 * kTurn) << " ? v : ref + remainder(d, " << hex_double(kTurn) << ");\n}\n\n";
}

// The includes and the guards every source starts with: the arithmetic must round each
// operation to double (no x87 excess precision) and, when the source multiplies and adds
// (`multiply_adds`), must not fuse the two into one FMA, or the answers would differ from
// marsyn's in the last bits (docs/deploy.md).
inline std::string source_preamble(const std::string& prefix, bool multiply_adds) {
  const std::string P = upper(prefix);
  std::ostringstream o;
  o << "#include \"" << prefix << ".h\"\n\n#include <float.h>\n#include <math.h>\n#include <stdint.h>\n\n"
    << "#if defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD != 0 && FLT_EVAL_METHOD != -1 && !defined(" << P
    << "_ALLOW_EXCESS_PRECISION)\n"
    << "#error \"" << prefix << ".c needs double arithmetic without excess precision (FLT_EVAL_METHOD 0); see docs/deploy.md\"\n"
    << "#endif\n";
  if (multiply_adds)
    o << "/* No fused multiply-add: C99's own switch, which clang honours. gcc ignores it, contracts nothing\n"
      << " * under -std=c99 but does in its GNU modes (-std=gnu99, the default) where the target has FMA. */\n"
      << "#if defined(__clang__)\n#pragma STDC FP_CONTRACT OFF\n#endif\n"
      << "#if defined(__GNUC__) && !defined(__clang__) && defined(__FP_FAST_FMA) && !defined(__STRICT_ANSI__) && !defined(" << P
      << "_NO_CONTRACTION)\n"
      << "#error \"" << prefix << ".c: gcc fuses a * b + c into one FMA in GNU modes on this target; compile with -std=c99, or with "
      << "-ffp-contract=off and -D" << P << "_NO_CONTRACTION (docs/deploy.md)\"\n"
      << "#endif\n";
  o << "\n";
  return o.str();
}

// The symbol prefix a C request asks for (its own, else the agent's name made into one); false
// with the reason in r.message when the prefix or the encoding is bad. Every tracker accepts
// abcd's encodings, so that one request can export a folder of mixed controllers.
inline bool c_request_prefix(const ExportRequest& req, const std::string& agent, std::string& prefix, ExportResult& r) {
  prefix = req.prefix.empty() ? default_prefix(agent) : req.prefix;
  if (!is_c_identifier(prefix)) {
    r.message = "prefix '" + prefix + "' is not a C identifier ([A-Za-z_][A-Za-z0-9_]*)";
    return false;
  }
  if (req.encoding != "auto" && req.encoding != "dense" && req.encoding != "rle") {
    r.message = "unknown encoding '" + req.encoding + "'; expected auto, dense or rle";
    return false;
  }
  return true;
}

inline void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot open " + path.string() + " for writing");
  out << text;
  if (!out) throw std::runtime_error("write to " + path.string() + " failed");
}

// Writes <out_dir>/<prefix>.h and .c (the folder created when missing) and lists them in
// r.files; false with the reason in r.message.
inline bool write_header_and_source(const ExportRequest& req, const std::string& prefix, const std::string& header,
                                    const std::string& source, ExportResult& r) {
  try {
    const std::filesystem::path dir(req.out_dir.empty() ? "." : req.out_dir);
    std::filesystem::create_directories(dir);
    const std::filesystem::path h = dir / (prefix + ".h"), c = dir / (prefix + ".c");
    write_text(h, header);
    write_text(c, source);
    r.files = {h.string(), c.string()};
  } catch (const std::exception& e) {
    r.message = e.what();
    return false;
  }
  return true;
}

}  // namespace marsyn::c_source
