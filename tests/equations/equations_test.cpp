// Equation models (issue 15) against the C++ plugins they transcribe: written in the plugins'
// operation order, they must give bit-identical values, derivatives (DualD, DualD2) and interval
// enclosures (Interval, DualI, FastInterval, DualFI), the same footprints and the same
// field_independent_of. A model using every supported function passes the generic soundness
// checks every plugin passes (tests/support/dynamics_checks.hpp).
#include <gtest/gtest.h>

#include <bit>
#include <random>

#include "dynamics_cartpole/src/cartpole.hpp"
#include "dynamics_checks.hpp"
#include "dynamics_double_integrator/src/double_integrator.hpp"
#include "dynamics_pendulum/src/pendulum.hpp"
#include "dynamics_unicycle/src/unicycle.hpp"
#include "equations/equation_dynamics.hpp"

namespace {

using marsyn::DualD;
using marsyn::DualD2;
using marsyn::DualFI;
using marsyn::DualI;
using marsyn::Dynamics;
using marsyn::FastInterval;
using marsyn::Interval;
using marsyn::equations::EquationDynamics;
using marsyn::equations::EquationError;
using marsyn::equations::EquationSpec;

EquationSpec unicycle_spec() {
  EquationSpec s;
  s.states = {"x", "y", "theta"};
  s.inputs = {"v", "omega"};
  s.field = {{"x", "v * cos(theta)"}, {"y", "v * sin(theta)"}, {"theta", "omega"}};
  return s;
}

EquationSpec double_integrator_spec() {
  EquationSpec s;
  s.states = {"p", "v"};
  s.inputs = {"a"};
  s.field = {{"p", "v"}, {"v", "a"}};
  return s;
}

EquationSpec pendulum_spec(double gain = 0.2) {
  EquationSpec s;
  s.states = {"angle", "rate"};
  s.inputs = {"torque"};
  s.constants = {{"input_gain", gain}};
  s.field = {{"angle", "rate"}, {"rate", "input_gain * torque - sin(angle)"}};
  return s;
}

// cartpole.hpp's vector_field, operation by operation (mt = mc + mp folded, as the plugin does).
EquationSpec cartpole_spec() {
  EquationSpec s;
  s.states = {"z", "z_dot", "theta", "theta_dot"};
  s.inputs = {"force"};
  s.constants = {{"gravity", 9.8}, {"cart_mass", 1.0}, {"pole_mass", 0.1}, {"half_pole_length", 0.5},
                 {"tip_length", 0.5}, {"rail_height", 0.6}};
  s.definitions = {
      {"push", "(force + pole_mass * half_pole_length * (theta_dot * theta_dot) * sin(theta)) / (cart_mass + pole_mass)"},
      {"th_dd", "(gravity * sin(theta) - cos(theta) * push) / (half_pole_length * (4.0 / 3.0 - (pole_mass / "
                "(cart_mass + pole_mass)) * (cos(theta) * cos(theta))))"}};
  s.field = {{"z", "z_dot"},
             {"z_dot", "push - (pole_mass * half_pole_length / (cart_mass + pole_mass)) * th_dd * cos(theta)"},
             {"theta", "theta_dot"},
             {"theta_dot", "th_dd"}};
  s.footprints = {{"pendulum_tip", {"z + tip_length * sin(theta)", "rail_height + tip_length * cos(theta)"}}};
  return s;
}

// Bit equality through every layer of a scalar.
bool same(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
bool same(const Interval& a, const Interval& b) { return same(a.lower(), b.lower()) && same(a.upper(), b.upper()); }
bool same(const FastInterval& a, const FastInterval& b) { return same(a.lower(), b.lower()) && same(a.upper(), b.upper()); }
template <class T>
bool same(const marsyn::Dual<T>& a, const marsyn::Dual<T>& b) {
  if (a.n != b.n || !same(a.v, b.v)) return false;
  for (int i = 0; i < a.n; ++i)
    if (!same(a.d[i], b.d[i])) return false;
  return true;
}

template <class S>
S seed(double lo, double hi, int slot, int count);
template <> double seed<double>(double lo, double, int, int) { return lo; }
template <> Interval seed<Interval>(double lo, double hi, int, int) { return Interval(lo, hi); }
template <> FastInterval seed<FastInterval>(double lo, double hi, int, int) { return FastInterval(lo, hi); }
template <> DualD seed<DualD>(double lo, double, int slot, int count) { return DualD::variable(lo, slot, count); }
template <> DualI seed<DualI>(double lo, double hi, int slot, int count) { return DualI::variable(Interval(lo, hi), slot, count); }
template <> DualFI seed<DualFI>(double lo, double hi, int slot, int count) {
  return DualFI::variable(FastInterval(lo, hi), slot, count);
}
template <> DualD2 seed<DualD2>(double lo, double, int slot, int count) { return marsyn::second_order_variable(lo, slot, count); }

struct Range {
  std::vector<double> lo, hi;  // states then inputs
};

// The field and every footprint of `eq` and `plugin`, in scalar type S, at random points (point
// types) or random boxes (interval types) of `r`: bit-identical.
template <class S>
void expect_same_in(const Dynamics& eq, const Dynamics& plugin, const Range& r, int samples = 300) {
  const int n = plugin.state_dim(), m = plugin.input_dim();
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int s = 0; s < samples; ++s) {
    std::vector<S> x(n), u(m), a(n), b(n);
    for (int i = 0; i < n + m; ++i) {
      const double lo = r.lo[i] + unit(rng) * (r.hi[i] - r.lo[i]);
      const double hi = std::min(r.hi[i], lo + unit(rng) * 0.2 * (r.hi[i] - r.lo[i]));
      (i < n ? x[i] : u[i - n]) = seed<S>(lo, hi, i, n + m);
    }
    eq.field(x.data(), u.data(), a.data());
    plugin.field(x.data(), u.data(), b.data());
    for (int i = 0; i < n; ++i) ASSERT_TRUE(same(a[i], b[i])) << "coordinate " << i << " of sample " << s;
    if constexpr (!std::is_same_v<S, FastInterval> && !std::is_same_v<S, DualFI> && !std::is_same_v<S, DualI>) {
      for (int f = 0; f < static_cast<int>(plugin.footprints().size()); ++f) {
        S pa[2], pb[2];
        eq.footprint(f, x.data(), pa);
        plugin.footprint(f, x.data(), pb);
        for (int c = 0; c < 2; ++c) ASSERT_TRUE(same(pa[c], pb[c])) << "footprint " << f << " coordinate " << c;
      }
    }
  }
}

void expect_same_model(const EquationSpec& spec, const Dynamics& plugin, const Range& r) {
  const EquationDynamics eq(spec);
  EXPECT_EQ(eq.state_dim(), plugin.state_dim());
  EXPECT_EQ(eq.input_dim(), plugin.input_dim());
  EXPECT_EQ(eq.state_names(), plugin.state_names());
  EXPECT_EQ(eq.input_names(), plugin.input_names());
  EXPECT_EQ(eq.footprints(), plugin.footprints());
  EXPECT_EQ(eq.field_independent_of(), plugin.field_independent_of());
  EXPECT_TRUE(eq.has_second_order());
  expect_same_in<double>(eq, plugin, r);
  expect_same_in<DualD>(eq, plugin, r);
  expect_same_in<DualD2>(eq, plugin, r);
  expect_same_in<Interval>(eq, plugin, r);
  expect_same_in<DualI>(eq, plugin, r);
  expect_same_in<FastInterval>(eq, plugin, r);
  expect_same_in<DualFI>(eq, plugin, r);
}

TEST(EquationModels, UnicycleIsBitIdenticalToThePlugin) {
  expect_same_model(unicycle_spec(), marsyn::models::Unicycle(), {{-5, -5, -7, -2, -3}, {5, 5, 7, 2, 3}});
}

TEST(EquationModels, DoubleIntegratorIsBitIdenticalToThePlugin) {
  expect_same_model(double_integrator_spec(), marsyn::models::DoubleIntegrator(), {{-5, -3, -2}, {5, 3, 2}});
}

TEST(EquationModels, PendulumIsBitIdenticalToThePlugin) {
  expect_same_model(pendulum_spec(), marsyn::models::Pendulum(), {{-4, -3, -2}, {4, 3, 2}});
  marsyn::Params p;
  p.set("input_gain", 0.35);
  expect_same_model(pendulum_spec(0.35), marsyn::models::Pendulum(p), {{-4, -3, -2}, {4, 3, 2}});
}

TEST(EquationModels, CartPoleIsBitIdenticalToThePlugin) {
  expect_same_model(cartpole_spec(), marsyn::models::CartPole(), {{-2, -2, 0, -4, -10}, {2, 2, 6.3, 4, 10}});
}

// A different constant changes the values: the comparison above is not vacuous.
TEST(EquationModels, AChangedConstantIsSeen) {
  EquationSpec s = cartpole_spec();
  s.constants[2].second = 0.1000001;  // pole_mass
  const EquationDynamics eq(s);
  const marsyn::models::CartPole plugin;
  const double x[4] = {0.1, 0.2, 1.0, 0.5}, u[1] = {0.3};
  double a[4], b[4];
  eq.field(x, u, a);
  plugin.field(x, u, b);
  EXPECT_NE(a[1], b[1]);
  EXPECT_NE(eq.type(), EquationDynamics(cartpole_spec()).type());
  EXPECT_EQ(EquationDynamics(cartpole_spec()).type(), EquationDynamics(cartpole_spec()).type());
}

// Every supported function and operator, with derivatives checked against differences and
// enclosures against points (Interval/DualI), and FastInterval/DualFI enclosures against points.
EquationSpec zoo_spec() {
  EquationSpec s;
  s.states = {"a", "b", "c"};
  s.inputs = {"u"};
  s.constants = {{"k", 0.7}};
  s.field = {{"a", "sin(a) * cos(b) + tan(0.5 * c) - exp(-a^2) + log(2 + b^2)"},
             {"b", "sqrt(1 + c^2) * atan(a - b) / (2 + cos(a)) + u^3 - 2^-1 * b^-2"},
             {"c", "-(a - k)^2 + pi * u / (1.5 + sin(c)) + (b * c)^4"}};
  return s;
}

TEST(EquationModels, EverySupportedFunctionIsDifferentiatedAndEnclosed) {
  const EquationDynamics eq(zoo_spec());
  const marsyn::testing::SampleBox box{{-1.0, 0.5, -1.0, -1.0}, {1.0, 2.0, 1.0, 1.0}};
  marsyn::testing::expect_ad_matches_finite_differences(eq, box, 100);
  marsyn::testing::expect_interval_encloses_points(eq, box, 100, 40);
  // FastInterval and DualFI (the tracker's types) enclose the point values and Jacobians.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int t = 0; t < 200; ++t) {
    double lo[4], hi[4];
    FastInterval x[3], u[1], f[3];
    DualFI xd[3], ud[1], fd[3];
    for (int i = 0; i < 4; ++i) {
      lo[i] = box.lo[i] + unit(rng) * (box.hi[i] - box.lo[i]);
      hi[i] = std::min(box.hi[i], lo[i] + 0.3 * unit(rng));
      (i < 3 ? x[i] : u[0]) = FastInterval(lo[i], hi[i]);
      (i < 3 ? xd[i] : ud[0]) = DualFI::variable(FastInterval(lo[i], hi[i]), i, 4);
    }
    eq.field(x, u, f);
    eq.field(xd, ud, fd);
    for (int p = 0; p < 20; ++p) {
      double z[4];
      DualD zd[4], g[3];
      for (int i = 0; i < 4; ++i) {
        z[i] = lo[i] + unit(rng) * (hi[i] - lo[i]);
        zd[i] = DualD::variable(z[i], i, 4);
      }
      eq.field(zd, zd + 3, g);
      for (int i = 0; i < 3; ++i) {
        ASSERT_LE(f[i].lower(), g[i].v);
        ASSERT_GE(f[i].upper(), g[i].v);
        for (int j = 0; j < 4; ++j) {
          ASSERT_LE(fd[i].d[j].lower(), g[i].d[j]) << i << " " << j;
          ASSERT_GE(fd[i].d[j].upper(), g[i].d[j]) << i << " " << j;
        }
      }
    }
  }
}

// The DualD2 layer is the exact Hessian: compare with differences of the DualD Jacobian.
TEST(EquationModels, SecondDerivativesMatchDifferencedJacobians) {
  const EquationDynamics eq(zoo_spec());
  const double z[4] = {0.3, 1.1, -0.4, 0.6};
  DualD2 x2[4], f2[3];
  for (int i = 0; i < 4; ++i) x2[i] = marsyn::second_order_variable(z[i], i, 4);
  eq.field(x2, x2 + 3, f2);
  for (int b = 0; b < 4; ++b) {
    DualD p[4], m[4], fp[3], fm[3];
    const double h = 1e-6;
    for (int i = 0; i < 4; ++i) {
      p[i] = DualD::variable(z[i] + (i == b ? h : 0), i, 4);
      m[i] = DualD::variable(z[i] - (i == b ? h : 0), i, 4);
    }
    eq.field(p, p + 3, fp);
    eq.field(m, m + 3, fm);
    for (int i = 0; i < 3; ++i)
      for (int a = 0; a < 4; ++a)
        EXPECT_NEAR(marsyn::second_derivative(f2[i], a, b), (fp[i].d[a] - fm[i].d[a]) / (2 * h), 1e-5)
            << "d2 f" << i << " / dz" << a << " dz" << b;
  }
}

// x^2 is the tight square for intervals (x * x of [-1, 2] is [-2, 4], x^2 is [0, 4]).
TEST(EquationModels, EvenPowersAreTightOverIntervals) {
  EquationSpec s;
  s.states = {"x"};
  s.inputs = {"u"};
  s.field = {{"x", "x^2 + u"}};
  const EquationDynamics eq(s);
  const FastInterval x[1] = {FastInterval(-1.0, 2.0)}, u[1] = {FastInterval(0.0)};
  FastInterval f[1];
  eq.field(x, u, f);
  EXPECT_EQ(f[0].lower(), 0.0);
  EXPECT_EQ(f[0].upper(), 4.0);
  const Interval xi[1] = {Interval(-1.0, 2.0)}, ui[1] = {Interval(0.0)};
  Interval fi[1];
  eq.field(xi, ui, fi);
  EXPECT_EQ(fi[0].lower(), 0.0);
  EXPECT_EQ(fi[0].upper(), 4.0);
}

TEST(EquationModels, FieldIndependenceFollowsTheStatesRead) {
  EquationSpec s = unicycle_spec();
  s.states.push_back("w");
  s.field.push_back({"w", "0.5 * x"});  // w' reads x: only y and w stay free
  const EquationDynamics eq(s);
  EXPECT_EQ(eq.field_independent_of(), (std::vector<bool>{false, true, false, true}));
}

TEST(EquationModels, CommonSubexpressionsAreComputedOnce) {
  const EquationDynamics eq(cartpole_spec());
  int sines = 0, cosines = 0;
  for (const auto& in : eq.field_program().code()) {
    sines += in.code == marsyn::equations::Program::Code::Sin;
    cosines += in.code == marsyn::equations::Program::Code::Cos;
  }
  EXPECT_EQ(sines, 1);
  EXPECT_EQ(cosines, 1);
}

// ---- errors (the located forms are tested through `marsyn check`, equations_cli_test) ----

void expect_error(const EquationSpec& s, const std::string& section, int index, const std::string& text, long offset = -2) {
  try {
    EquationDynamics eq(s);
    ADD_FAILURE() << "accepted; expected: " << text;
  } catch (const EquationError& e) {
    EXPECT_EQ(e.section(), section) << e.what();
    EXPECT_EQ(e.index(), index) << e.what();
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    if (offset != -2) EXPECT_EQ(e.offset(), offset) << e.what();
  }
}

TEST(EquationErrors, EachClassIsReportedWithItsPlace) {
  EquationSpec s = unicycle_spec();
  s.field[0].text = "v * cos(thetta)";
  expect_error(s, "field", 0, "unknown symbol 'thetta'", 8);
  s = unicycle_spec();
  s.field[1].text = "v * (sin(theta)";
  expect_error(s, "field", 1, "syntax error at column 16 of the expression: expected ')'", 15);
  s = unicycle_spec();
  s.field[1].text = "v ** sin(theta)";
  expect_error(s, "field", 1, "syntax error at column 4", 3);
  s = unicycle_spec();
  s.field.pop_back();
  expect_error(s, "field", -1, "the state 'theta' has no equation");
  s = unicycle_spec();
  s.inputs[1] = "x";
  expect_error(s, "inputs", 1, "the name 'x' is used twice (also a state)");
  s = unicycle_spec();
  s.constants = {{"v", 1.0}};
  expect_error(s, "constants", 0, "the name 'v' is used twice (also an input)");
  s = unicycle_spec();
  s.field[0].text = "v * abs(theta)";
  expect_error(s, "field", 0, "unsupported function 'abs' (supported: sin, cos, tan, exp, log, sqrt, atan", 4);
  s = unicycle_spec();
  s.constants = {{"c", std::numeric_limits<double>::infinity()}};
  expect_error(s, "constants", 0, "the constant 'c' is not finite");
  s = unicycle_spec();
  s.constants = {{"c", 0.0}};
  s.field[0].text = "v / c * cos(theta) + 1 / c";
  expect_error(s, "field", 0, "not finite", 21);
  s = unicycle_spec();
  s.field[0].text = "v^theta";
  expect_error(s, "field", 0, "the exponent after '^' must be an integer constant", 2);
  s = unicycle_spec();
  s.field[0].text = "v^0.5";
  expect_error(s, "field", 0, "must be an integer", 2);
  s = unicycle_spec();
  s.field.push_back({"x", "v"});
  expect_error(s, "field", 3, "a second equation for the state 'x'");
  s = unicycle_spec();
  s.field[2].text = "1e999";
  expect_error(s, "field", 2, "outside the range of finite doubles", 0);
  s = unicycle_spec();
  s.footprints = {{"nose", {"x + 0.3 * cos(theta)", "y + v"}}};
  expect_error(s, "footprints", 0, "reads the input 'v'");
  s = unicycle_spec();
  s.states[0] = "sin";
  expect_error(s, "states", 0, "reserved");
  s = unicycle_spec();
  s.field[2].text = std::string(5000, '(') + "omega" + std::string(5000, ')');
  expect_error(s, "field", 2, "nested more than 200 levels");
  s = unicycle_spec();
  s.field[2].text = std::string(150, '(') + "omega" + std::string(150, ')');
  EXPECT_NO_THROW(EquationDynamics{s});
  std::string chain = "omega";
  for (int i = 0; i < 3000; ++i) chain += "^1";
  s.field[2].text = chain;
  expect_error(s, "field", 2, "nested more than 200 levels");
  s.field[2].text = "omega * " + std::string(3000, '-') + "1";
  expect_error(s, "field", 2, "nested more than 200 levels");
}

}  // namespace

namespace {

// Random text from the expression alphabet: every input is either a model or an EquationError
// whose offset lies inside the text; never a crash, another exception or a hang.
TEST(EquationErrors, RandomTextIsRejectedCleanly) {
  const std::string alphabet = "xvtheaomgincosqrlp0123456789.e+-*/^() ,_";
  std::mt19937_64 rng(99);
  int accepted = 0;
  for (int t = 0; t < 5000; ++t) {
    std::string text;
    const int len = 1 + static_cast<int>(rng() % 24);
    for (int i = 0; i < len; ++i) text += alphabet[rng() % alphabet.size()];
    EquationSpec s = unicycle_spec();
    s.field[2].text = text;
    try {
      EquationDynamics eq(s);
      ++accepted;
    } catch (const EquationError& e) {
      EXPECT_GE(e.offset(), 0) << text;
      EXPECT_LE(e.offset(), static_cast<long>(text.size())) << text;
    }
  }
  EXPECT_GT(accepted, 0);
}

}  // namespace
