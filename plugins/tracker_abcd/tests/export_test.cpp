// Controller export (docs/deploy.md): the generated C compiles under gcc -std=c99 -Wall -Wextra
// -Werror -pedantic and, linked into a C program, answers >= 1e5 sampled (x, k) exactly as the
// C++ Controller::input (status and input bits) and the monitor <prefix>_inside exactly as
// GridController::winning, in both table encodings, for the pendulum, a
// drone of the multi-drone case and a whole-domain (time-invariant) controller; the SCOTS file
// read back lists exactly the controller's (cell, k) -> input pairs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <sstream>

#include "agents.hpp"
#include "deploy/c_answers.hpp"
#include "dynamics_double_integrator/src/double_integrator.hpp"
#include "export_formats.hpp"
#include "marsyn/periodic.hpp"

using namespace marsyn;
using namespace marsyn::abcd;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path p = fs::path(::testing::TempDir()) / ("marsyn_export_" + name);
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

std::shared_ptr<const GridController> grid_controller(const TrackResult& r) {
  return std::dynamic_pointer_cast<const GridController>(r.controller);
}

const TrackResult& whole_domain() {
  static const TrackResult r = [] {
    ReachAvoidProblem p;
    p.dynamics = std::make_shared<models::DoubleIntegrator>();
    p.domain = {scenarios::vec({-1, -1}), scenarios::vec({1, 1})};
    p.safe = p.domain;
    p.target = {scenarios::vec({-0.2, -0.2}), scenarios::vec({0.2, 0.2})};
    p.eta_x = scenarios::vec({0.05, 0.05});
    p.eta_u = scenarios::vec({0.25});
    p.w = scenarios::vec({0, 0.02});
    p.input_bounds = {scenarios::vec({-2}), scenarios::vec({2})};
    AbcdTracker tracker;
    TrackOptions o;
    o.threads = 2;
    return tracker.reach_avoid(p, o);
  }();
  return r;
}

using Query = deploy_test::CQuery;

// States near the tube (inside and outside), exactly on cell boundaries and one ulp either side,
// non-finite and huge coordinates, and steps before, inside and after the horizon.
std::vector<Query> queries(const GridController& c, const std::vector<Eigen::VectorXd>& centres, const Eigen::VectorXd& spread,
                           int count, std::uint64_t seed) {
  const ControllerData& d = c.data();
  const int n = d.n, tables = d.tables();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Query> out;
  out.reserve(static_cast<size_t>(count));
  const double specials[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                             -std::numeric_limits<double>::infinity(), 1e300, -1e300, 1e19, -1e19, 9.3e18};
  for (int q = 0; q < count; ++q) {
    Query Q;
    const int kind = static_cast<int>(rng() % 20);
    Q.k = static_cast<std::int32_t>(rng() % static_cast<std::uint64_t>(tables + 4)) - 2;  // -2 .. T+1
    if (rng() % 50 == 0) Q.k = (rng() & 1) ? std::numeric_limits<std::int32_t>::max() : std::numeric_limits<std::int32_t>::min();
    const int kc = std::clamp<int>(Q.k, 0, static_cast<int>(centres.size()) - 1);
    Q.x.resize(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) Q.x[static_cast<size_t>(i)] = centres[static_cast<size_t>(kc)][i] + 1.3 * spread[i] * unit(rng);
    if (kind < 4) {  // a cell boundary of the step's tube box, maybe one ulp off
      const IndexBox& b = d.boxes[static_cast<size_t>(std::clamp(Q.k, 0, static_cast<int>(d.boxes.size()) - 1))];
      for (int i = 0; i < n; ++i) {
        const std::int64_t lo = b.lo[i] - 1, span = b.hi[i] - b.lo[i] + 3;
        const std::int64_t idx = lo + static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(std::max<std::int64_t>(1, span)));
        double x = d.origin[static_cast<size_t>(i)] + static_cast<double>(idx) * d.eta_x[static_cast<size_t>(i)];
        const int nudge = static_cast<int>(rng() % 3);
        if (nudge == 1) x = std::nextafter(x, -INFINITY);
        if (nudge == 2) x = std::nextafter(x, INFINITY);
        Q.x[static_cast<size_t>(i)] = x;
      }
    } else if (kind == 4) {  // a non-finite or huge coordinate
      Q.x[rng() % static_cast<std::uint64_t>(n)] = specials[rng() % (sizeof specials / sizeof specials[0])];
    } else if (kind == 5) {  // far away
      for (int i = 0; i < n; ++i) Q.x[static_cast<size_t>(i)] += 20.0 * spread[i] * unit(rng);
    }
    out.push_back(std::move(Q));
  }
  return out;
}

// Exports `c` as C with `encoding`, compiles it with the driver, answers `qs` in C, and compares
// every status and input bit for bit with GridController::input. Returns the status counts.
std::map<ControlStatus, int> check_c_against_cpp(const GridController& c, const std::vector<Query>& qs, const std::string& name,
                                                 const std::string& encoding, ExportResult* result_out = nullptr) {
  std::map<ControlStatus, int> counts;
  const fs::path dir = scratch(name + "_" + encoding);
  ExportRequest req;
  req.format = "c";
  req.out_dir = dir.string();
  req.prefix = name;
  req.encoding = encoding;
  const ExportResult r = c.export_to(req);
  EXPECT_TRUE(r.ok) << r.message;
  if (!r.ok) return counts;
  EXPECT_EQ(r.encoding, encoding == "auto" ? (r.rle_bytes < r.dense_bytes ? "rle" : "dense") : encoding);
  if (result_out) *result_out = r;
  const ControllerData& d = c.data();
  std::vector<deploy_test::CAnswer> answers;
  const std::string err = deploy_test::answer_in_c(dir, name, d.n, d.m, qs, answers);
  EXPECT_EQ(err, "");
  if (!err.empty()) return counts;
  std::vector<double> u(static_cast<size_t>(d.m));
  int mismatches = 0;
  for (size_t q = 0; q < qs.size(); ++q) {
    const Query& Q = qs[q];
    const deploy_test::CAnswer& A = answers[q];
    const ControlStatus expected = c.input(Q.x.data(), Q.k, u.data());
    ++counts[expected];
    const bool inside = c.winning(Q.x.data(), Q.k);
    bool same = A.status == static_cast<std::int32_t>(expected) && A.inside == (inside ? 1 : 0);
    if (same && expected == ControlStatus::Ok) same = std::memcmp(u.data(), A.u.data(), sizeof(double) * u.size()) == 0;
    if (!same && ++mismatches <= 5) {
      std::ostringstream x;
      x.precision(17);
      for (double v : Q.x) x << v << " ";
      ADD_FAILURE() << name << "/" << encoding << ": k = " << Q.k << ", x = " << x.str() << ": C status " << A.status
                    << ", inside " << A.inside << "; C++ " << static_cast<int>(expected) << ", winning " << inside;
    }
  }
  EXPECT_EQ(mismatches, 0);
  return counts;
}

std::vector<Eigen::VectorXd> box_centres(const Box& b) { return {(b.lo + b.hi) / 2}; }

}  // namespace

TEST(ExportC, PendulumBitIdenticalInBothEncodings) {
  const auto& a = marsyn::abcd::testing::agent("pendulum");
  ASSERT_EQ(a.result.status, TrackerStatus::ControllerFound) << a.result.message;
  const auto c = grid_controller(a.result);
  ASSERT_TRUE(c);
  const auto qs = queries(*c, a.problem.nominal.x, a.problem.tube.eps, 120000, 1);
  for (const char* enc : {"dense", "rle"}) {
    auto counts = check_c_against_cpp(*c, qs, "pendulum", enc);
    EXPECT_GT(counts[ControlStatus::Ok], 10000) << enc;
    EXPECT_GT(counts[ControlStatus::OutsideDomain], 10000) << enc;
    EXPECT_GT(counts[ControlStatus::OutsideHorizon], 2000) << enc;
  }
}

TEST(ExportC, DroneBitIdenticalInBothEncodings) {
  const auto& a = marsyn::abcd::testing::agent("drone");
  ASSERT_EQ(a.result.status, TrackerStatus::ControllerFound) << a.result.message;
  const auto c = grid_controller(a.result);
  ASSERT_TRUE(c);
  const auto qs = queries(*c, a.problem.nominal.x, a.problem.tube.eps, 120000, 2);
  for (const char* enc : {"dense", "rle"}) {
    auto counts = check_c_against_cpp(*c, qs, "drone1", enc);
    EXPECT_GT(counts[ControlStatus::Ok], 10000) << enc;
    EXPECT_GT(counts[ControlStatus::OutsideDomain], 10000) << enc;
    EXPECT_GT(counts[ControlStatus::OutsideHorizon], 2000) << enc;
  }
}

// The pendulum's angle is periodic: a state read on another branch (whole turns away) gets the
// answer of its lift, in C exactly as in C++ (the same lift), and the source says so.
TEST(ExportC, PendulumReadsItsAngleOnAnyBranch) {
  const auto& a = marsyn::abcd::testing::agent("pendulum");
  const auto c = grid_controller(a.result);
  ASSERT_TRUE(c);
  ASSERT_TRUE(c->any_periodic());
  const auto base = queries(*c, a.problem.nominal.x, a.problem.tube.eps, 20000, 4);
  std::vector<Query> turned;
  std::mt19937_64 rng(9);
  const double turns[] = {-3, -1, 1, 2};
  for (const Query& q : base) {
    Query t = q;
    t.x[0] += turns[rng() % 4] * kTurn;
    turned.push_back(t);
  }
  auto counts = check_c_against_cpp(*c, turned, "pendulum_turned", "dense");
  EXPECT_GT(counts[ControlStatus::Ok], 2000);
  // The lifted reading is the state up to about 1e-15: the same cell but at cell boundaries.
  int same = 0, ok = 0;
  double u0[1], u1[1];
  const ControllerData& d = c->data();
  for (size_t q = 0; q < base.size(); ++q) {
    // A state on a cell boundary (a fifth of the queries, to the ulp) may read as its neighbour.
    const double cells = (base[q].x[0] - d.origin[0]) / d.eta_x[0];
    if (std::abs(cells - std::nearbyint(cells)) < 1e-9) continue;
    if (c->input(base[q].x.data(), base[q].k, u0) != ControlStatus::Ok) continue;
    ++ok;
    if (c->input(turned[q].x.data(), turned[q].k, u1) == ControlStatus::Ok && u0[0] == u1[0]) ++same;
  }
  EXPECT_GT(ok, 2000);
  EXPECT_GE(same, ok * 999 / 1000) << same << " of " << ok;
  const fs::path dir = scratch("pendulum_src");
  ExportRequest req;
  req.format = "c";
  req.out_dir = dir.string();
  ASSERT_TRUE(c->export_to(req).ok);
  std::ifstream in(dir / "pendulum.c");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("x[0] = pendulum_lift(x_read[0], pendulum_ref[k][0]);"), std::string::npos);
}

TEST(ExportC, WholeDomainControllerWithTargetCells) {
  const auto& r = whole_domain();
  ASSERT_EQ(r.status, TrackerStatus::ControllerFound) << r.message;
  const auto c = grid_controller(r);
  ASSERT_TRUE(c);
  const auto qs = queries(*c, box_centres({scenarios::vec({-1, -1}), scenarios::vec({1, 1})}), scenarios::vec({0.8, 0.8}),
                          100000, 3);
  ExportResult res;
  auto counts = check_c_against_cpp(*c, qs, "reach", "auto", &res);
  EXPECT_GT(counts[ControlStatus::Ok], 10000);
  EXPECT_GT(counts[ControlStatus::OutsideDomain], 5000);
  EXPECT_GT(counts[ControlStatus::OutsideHorizon], 1000);  // target cells (k is ignored)
  EXPECT_EQ(res.const_data_bytes, std::min(res.dense_bytes, res.rle_bytes));
}

TEST(ExportC, TablesAreSizedToTheController) {
  const auto& a = marsyn::abcd::testing::agent("pendulum");
  const auto c = grid_controller(a.result);
  ASSERT_TRUE(c);
  const CTableSizes s = c_table_sizes(c->data());
  // A u16 per entry is what the .ctrl file stores; the palette code needs fewer bits.
  EXPECT_LT(s.bits, 16);
  EXPECT_GE(1ll << s.bits, s.palette + 1);
  EXPECT_LT(s.dense, s.entries * 2);
  EXPECT_GT(s.runs, 0);
  EXPECT_LE(s.runs, s.entries);
}

TEST(ExportC, BadRequestsAreClearErrors) {
  const auto& a = marsyn::abcd::testing::agent("pendulum");
  const auto& c = *a.result.controller;
  const fs::path dir = scratch("bad");
  auto attempt = [&](const std::string& format, const std::string& prefix, const std::string& encoding) {
    ExportRequest req;
    req.format = format;
    req.out_dir = dir.string();
    req.prefix = prefix;
    req.encoding = encoding;
    return c.export_to(req);
  };
  auto r = attempt("c", "1abc", "auto");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("not a C identifier"), std::string::npos) << r.message;
  r = attempt("c", "a-b", "auto");
  EXPECT_FALSE(r.ok);
  r = attempt("c", "ok_name", "huffman");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("unknown encoding"), std::string::npos) << r.message;
  r = attempt("matlab", "", "auto");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("unknown export format"), std::string::npos) << r.message;
  EXPECT_TRUE(fs::is_empty(dir));
  // An output folder that cannot be created (a file is in the way).
  std::ofstream(dir / "file") << "x";
  ExportRequest req;
  req.format = "c";
  req.out_dir = (dir / "file" / "sub").string();
  r = c.export_to(req);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.message.empty());
  EXPECT_TRUE(is_c_identifier("_x9"));
  EXPECT_FALSE(is_c_identifier(""));
  EXPECT_EQ(default_prefix("drone-1"), "drone_1");
  EXPECT_EQ(default_prefix("7up"), "c_7up");
}

// ---- SCOTS v0.2 ----------------------------------------------------------------------------

namespace {

struct ScsFile {
  std::vector<std::string> lines;
  std::map<std::string, std::vector<double>> state, input;  // ETA, LOWER_LEFT, UPPER_RIGHT
  int state_dim = 0, input_dim = 0;
  unsigned long long rows = 0, cols = 0;
  std::vector<std::pair<unsigned long long, unsigned long long>> pairs;
};

// A strict reader of the layout SCOTS' write_to_file(StaticController) produces (and dtControl
// parses by line position).
ScsFile read_scs(const fs::path& path) {
  ScsFile f;
  std::ifstream in(path);
  for (std::string l; std::getline(in, l);) f.lines.push_back(l);
  size_t p = 0;
  auto expect = [&](const std::string& s) {
    if (p >= f.lines.size() || f.lines[p] != s)
      throw std::runtime_error("line " + std::to_string(p + 1) + ": expected '" + s + "', got '" +
                               (p < f.lines.size() ? f.lines[p] : "EOF") + "'");
    ++p;
  };
  auto grid = [&](const std::string& text, int& dim, std::map<std::string, std::vector<double>>& v) {
    expect("#SCOTS:" + text);
    expect("#TYPE:UNIFORMGRID");
    expect("#MEMBER:DIM");
    dim = std::stoi(f.lines.at(p++));
    for (const char* name : {"ETA", "LOWER_LEFT", "UPPER_RIGHT"}) {
      expect(std::string("#VECTOR:") + name);
      expect("#BEGIN:" + std::to_string(dim));
      for (int i = 0; i < dim; ++i) v[name].push_back(std::stod(f.lines.at(p++)));
      expect("#END");
    }
  };
  expect("#SCOTS:v0.2");
  expect("#TYPE:STATICCONTROLLER");
  grid("STATE_SPACE", f.state_dim, f.state);
  grid("INPUT_SPACE", f.input_dim, f.input);
  expect("#TYPE:WINNINGDOMAIN");
  expect("#SCOTS:i (state) j_0 ... j_n (valid inputs)");
  expect("#MATRIX:DATA");
  if (p != 32u + 3u * static_cast<unsigned>(f.state_dim + f.input_dim) - 1u)
    throw std::runtime_error("the winning domain does not start where dtControl expects it");
  {
    std::istringstream s(f.lines.at(p).substr(std::string("#BEGIN:").size()));
    if (f.lines[p].rfind("#BEGIN:", 0) != 0) throw std::runtime_error("no #BEGIN");
    s >> f.rows >> f.cols;
    ++p;
  }
  for (; p < f.lines.size() && f.lines[p] != "#END"; ++p) {
    std::istringstream s(f.lines[p]);
    unsigned long long i, j;
    std::string rest;
    if (!(s >> i >> j) || (s >> rest)) throw std::runtime_error("bad data line " + f.lines[p]);
    f.pairs.emplace_back(i, j);
  }
  expect("#END");
  if (p != f.lines.size()) throw std::runtime_error("trailing lines");
  return f;
}

void check_scs(const GridController& c, const std::string& name) {
  const fs::path dir = scratch("scs_" + name);
  ExportRequest req;
  req.format = "scs";
  req.out_dir = dir.string();
  req.prefix = name;
  const ExportResult r = c.export_to(req);
  ASSERT_TRUE(r.ok) << r.message;
  ScsFile f;
  ASSERT_NO_THROW(f = read_scs(dir / (name + ".scs")));
  const ControllerData& d = c.data();
  const bool timed = !d.time_invariant;
  ASSERT_EQ(f.state_dim, d.n + (timed ? 1 : 0));
  ASSERT_EQ(f.input_dim, d.m);
  EXPECT_EQ(f.cols, 1u);
  // Grid point counts as dtControl computes them, and the SCOTS ids decoded first-coordinate-fastest.
  std::vector<unsigned long long> count, ucount;
  unsigned long long total = 1;
  for (int i = 0; i < f.state_dim; ++i) {
    const double e = f.state["ETA"][i];
    count.push_back(static_cast<unsigned long long>(std::llround((f.state["UPPER_RIGHT"][i] - f.state["LOWER_LEFT"][i]) / e)) + 1);
    total *= count.back();
  }
  EXPECT_EQ(f.rows, total);
  for (int j = 0; j < d.m; ++j) {
    ucount.push_back(static_cast<unsigned long long>(
                         std::llround((f.input["UPPER_RIGHT"][j] - f.input["LOWER_LEFT"][j]) / f.input["ETA"][j])) +
                     1);
    EXPECT_EQ(f.input["LOWER_LEFT"][j], d.u_lo[static_cast<size_t>(j)]);
    EXPECT_EQ(f.input["ETA"][j], d.eta_u[static_cast<size_t>(j)]);
  }
  // Every listed pair is a winning (cell, k) of the controller with the same input, found by
  // evaluating the controller at the listed grid point (the cell's centre, read from the file as
  // dtControl reconstructs it).
  InputGrid ug(d.u_lo, d.u_hi, d.eta_u);
  std::set<std::pair<int, std::int64_t>> listed;  // (k, linear index in table k)
  unsigned long long previous = 0;
  bool first = true;
  std::vector<double> u(static_cast<size_t>(d.m)), us(static_cast<size_t>(d.m));
  for (const auto& [id, uid] : f.pairs) {
    ASSERT_TRUE(first || id > previous) << "state ids not strictly increasing";
    first = false;
    previous = id;
    ASSERT_LT(id, total);
    unsigned long long rest = id;
    std::vector<double> x(static_cast<size_t>(d.n));
    int k = 0;
    for (int i = 0; i < f.state_dim; ++i) {
      const unsigned long long num = rest % count[static_cast<size_t>(i)];
      rest /= count[static_cast<size_t>(i)];
      if (i < d.n) x[static_cast<size_t>(i)] = f.state["LOWER_LEFT"][i] + static_cast<double>(num) * f.state["ETA"][i];
      else k = static_cast<int>(num);
    }
    unsigned long long urest = uid;
    std::int64_t j = 0;
    for (int q = 0; q < d.m; ++q) {
      const unsigned long long cq = ucount[static_cast<size_t>(q)];
      us[static_cast<size_t>(q)] = f.input["LOWER_LEFT"][q] + static_cast<double>(urest % cq) * f.input["ETA"][q];
      urest /= cq;
    }
    // back to marsyn's mixed radix (first input coordinate slowest)
    urest = uid;
    std::vector<unsigned long long> digits(static_cast<size_t>(d.m));
    for (int q = 0; q < d.m; ++q) {
      digits[static_cast<size_t>(q)] = urest % ucount[static_cast<size_t>(q)];
      urest /= ucount[static_cast<size_t>(q)];
    }
    for (int q = 0; q < d.m; ++q) j = j * static_cast<std::int64_t>(ug.count()[static_cast<size_t>(q)]) + static_cast<std::int64_t>(digits[static_cast<size_t>(q)]);
    ASSERT_EQ(c.input(x.data(), k, u.data()), ControlStatus::Ok) << "listed pair " << id << " " << uid;
    std::vector<double> expected(static_cast<size_t>(d.m));
    ug.value(j, expected.data());
    EXPECT_EQ(u, expected);
    for (int q = 0; q < d.m; ++q) EXPECT_NEAR(us[static_cast<size_t>(q)], u[static_cast<size_t>(q)], 1e-9);
    // the cell this centre lies in, in table k
    const IndexBox& b = d.boxes[static_cast<size_t>(k)];
    std::int64_t idx[kMaxDim];
    for (int i = 0; i < d.n; ++i) idx[i] = c.grid().index(i, x[static_cast<size_t>(i)]);
    ASSERT_TRUE(b.contains(idx));
    EXPECT_TRUE(listed.emplace(k, b.linear(idx)).second) << "a (cell, k) listed twice";
    EXPECT_EQ(d.inputs[static_cast<size_t>(d.offsets[static_cast<size_t>(k)] + b.linear(idx))], j);
  }
  // ... and every winning (cell, k) is listed.
  long long winning = 0;
  for (int k = 0; k < d.tables(); ++k) {
    const std::int64_t cells = d.boxes[static_cast<size_t>(k)].size();
    for (std::int64_t l = 0; l < cells; ++l) {
      const auto v = d.inputs[static_cast<size_t>(d.offsets[static_cast<size_t>(k)] + l)];
      if (v == kLosing || v == kTarget) continue;
      ++winning;
      EXPECT_TRUE(listed.count({k, l})) << "winning (cell " << l << ", k " << k << ") missing";
    }
  }
  EXPECT_EQ(winning, static_cast<long long>(f.pairs.size()));
  EXPECT_EQ(r.entries, winning);
  EXPECT_GT(winning, 100);
}

}  // namespace

TEST(ExportScs, PendulumListsExactlyTheControllersPairs) {
  const auto& a = marsyn::abcd::testing::agent("pendulum");
  const auto c = grid_controller(a.result);
  ASSERT_TRUE(c);
  check_scs(*c, "pendulum");
}

TEST(ExportScs, DroneListsExactlyTheControllersPairs) {
  const auto& a = marsyn::abcd::testing::agent("drone");
  const auto c = grid_controller(a.result);
  ASSERT_TRUE(c);
  check_scs(*c, "drone1");
}

TEST(ExportScs, WholeDomainControllerHasNoTimeCoordinate) {
  const auto& r = whole_domain();
  const auto c = grid_controller(r);
  ASSERT_TRUE(c);
  check_scs(*c, "reach");
}
