// FastInterval as the successor boxes use it: a model's field and Jacobian over it against
// high-precision values, and the rounding-mode discipline of the box computation
// (docs/soundness.md, section 2). The arithmetic itself is tested in interfaces/numerics/tests.
#include <gtest/gtest.h>

#include <boost/multiprecision/cpp_bin_float.hpp>
#include <algorithm>
#include <cfenv>
#include <random>
#include <stdexcept>
#include <vector>

#include "marsyn/fast_interval.hpp"
#include "track_scenarios.hpp"
#include "successor_box.hpp"
#include "tube.hpp"

using namespace marsyn;
using Big = boost::multiprecision::cpp_bin_float_100;

// The model's field with FastInterval / DualFI encloses the same model's field and Jacobian
// evaluated to 100 digits (the templated field instantiated with a multiprecision scalar) at
// points of the box, corners included.
TEST(FastInterval, CartPoleFieldAndJacobianEncloseHighPrecisionValues) {
  models::CartPole f;
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> un(-1, 1), w(0, 0.3);
  for (int it = 0; it < 400; ++it) {
    double lo[5], hi[5];
    const double centre[5] = {un(rng), 2 * un(rng), 3.14 + 1.5 * un(rng), 3 * un(rng), 7 * un(rng)};
    for (int i = 0; i < 5; ++i) {
      const double r = it % 4 == 0 ? 0.0 : w(rng);
      lo[i] = centre[i] - r;
      hi[i] = centre[i] + r;
    }
    FastInterval x[4], u[1], fx[4];
    DualFI xd[4], ud[1], fd[4];
    for (int i = 0; i < 4; ++i) {
      x[i] = FastInterval(lo[i], hi[i]);
      xd[i] = DualFI::variable(x[i], i, 4);
    }
    u[0] = FastInterval(lo[4], hi[4]);
    ud[0] = DualFI(u[0]);
    const Dynamics& dyn = f;
    dyn.field(x, u, fx);
    dyn.field(xd, ud, fd);
    for (int k = 0; k < 6; ++k) {
      Dual<Big> zd[4], vd[1], fzd[4];
      for (int i = 0; i < 4; ++i) {
        const double z = k == 0 ? lo[i] : k == 1 ? hi[i] : std::clamp(lo[i] + (hi[i] - lo[i]) * (0.5 + 0.5 * un(rng)), lo[i], hi[i]);
        zd[i] = Dual<Big>::variable(Big(z), i, 4);
      }
      vd[0] = Dual<Big>(Big(std::clamp(lo[4] + (hi[4] - lo[4]) * (0.5 + 0.5 * un(rng)), lo[4], hi[4])));
      f.vector_field(zd, vd, fzd);
      for (int i = 0; i < 4; ++i) {
        EXPECT_LE(Big(fx[i].lower()), fzd[i].v) << i;
        EXPECT_GE(Big(fx[i].upper()), fzd[i].v) << i;
        EXPECT_LE(Big(fd[i].v.lower()), fzd[i].v) << i;
        EXPECT_GE(Big(fd[i].v.upper()), fzd[i].v) << i;
        for (int j = 0; j < 4; ++j) {
          EXPECT_LE(Big(fd[i].derivative(j).lower()), fzd[i].derivative(j)) << i << j;
          EXPECT_GE(Big(fd[i].derivative(j).upper()), fzd[i].derivative(j)) << i << j;
        }
      }
    }
  }
}

namespace {

// A hand-written Dynamics (no DynamicsModel): its FastInterval overloads are the base class's
// conversions through the Interval ones. Optionally throws from the interval field.
class HandWrittenCartPole : public Dynamics {
 public:
  explicit HandWrittenCartPole(bool throws) : throws_(throws) {}
  std::string type() const override { return "hand"; }
  int state_dim() const override { return 4; }
  int input_dim() const override { return 1; }
  std::vector<std::string> state_names() const override { return {"a", "b", "c", "d"}; }
  std::vector<std::string> input_names() const override { return {"u"}; }
  void field(const double* x, const double* u, double* dx) const override { m_.vector_field(x, u, dx); }
  void field(const DualD* x, const DualD* u, DualD* dx) const override { m_.vector_field(x, u, dx); }
  void field(const Interval* x, const Interval* u, Interval* dx) const override {
    if (throws_) throw std::runtime_error("field failed");
    m_.vector_field(x, u, dx);
  }
  void field(const DualI* x, const DualI* u, DualI* dx) const override {
    if (throws_) throw std::runtime_error("field failed");
    m_.vector_field(x, u, dx);
  }
  using Dynamics::field;

 private:
  models::CartPole m_;
  bool throws_;
};

std::vector<Interval> crane_cell() {
  return {Interval(-0.0075, 0.0075), Interval(0.1, 0.135), Interval(3.10, 3.116), Interval(0.2, 0.264)};
}

}  // namespace

// compute() runs in round-to-nearest whatever the caller's mode, gives the same box, and hands
// the caller's mode back, also when the model throws.
TEST(FastInterval, SuccessorBoxRestoresTheCallersRoundingMode) {
  models::CartPole f;
  abcd::SuccessorBox sb(f, {0, 0.05, 0, 0}, abcd::SuccessorOptions{});
  const auto cell = crane_cell();
  const double u[1] = {1.3};
  double lo0[4], hi0[4];
  ASSERT_TRUE(sb.compute(cell.data(), u, lo0, hi0));
  EXPECT_EQ(std::fegetround(), FE_TONEAREST);
  for (int mode : {FE_UPWARD, FE_DOWNWARD, FE_TOWARDZERO}) {
    ASSERT_EQ(std::fesetround(mode), 0);
    double lo[4], hi[4];
    const bool ok = sb.compute(cell.data(), u, lo, hi);
    EXPECT_EQ(std::fegetround(), mode);
    std::fesetround(FE_TONEAREST);
    ASSERT_TRUE(ok);
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(lo[i], lo0[i]) << "mode " << mode;
      EXPECT_EQ(hi[i], hi0[i]) << "mode " << mode;
    }
  }

  HandWrittenCartPole throwing(true);
  abcd::SuccessorBox bad(throwing, {0, 0.05, 0, 0}, abcd::SuccessorOptions{});
  for (int mode : {FE_TONEAREST, FE_UPWARD, FE_DOWNWARD}) {
    std::fesetround(mode);
    double lo[4], hi[4];
    bool threw = false;
    try {
      bad.compute(cell.data(), u, lo, hi);
    } catch (const std::runtime_error&) {
      threw = true;
    }
    const int after = std::fegetround();
    std::fesetround(FE_TONEAREST);
    EXPECT_TRUE(threw);
    EXPECT_EQ(after, mode);
  }
}

// The base class's conversion path (hand-written Dynamics) gives a sound box too; with the same
// model it can only differ from the DynamicsModel path through sin/cos (Boost's reduction vs
// FastInterval's), so both boxes must contain the sampled reference point images.
TEST(FastInterval, HandWrittenDynamicsUsesTheConversionPath) {
  HandWrittenCartPole hand(false);
  models::CartPole crtp;
  abcd::SuccessorBox a(hand, {0, 0.05, 0, 0}, abcd::SuccessorOptions{}), b(crtp, {0, 0.05, 0, 0}, abcd::SuccessorOptions{});
  const auto cell = crane_cell();
  const double u[1] = {-2.1};
  double lo_a[4], hi_a[4], lo_b[4], hi_b[4];
  ASSERT_TRUE(a.compute(cell.data(), u, lo_a, hi_a));
  ASSERT_TRUE(b.compute(cell.data(), u, lo_b, hi_b));
  for (int i = 0; i < 4; ++i) {
    EXPECT_LT(lo_a[i], hi_a[i]);
    // Same enclosure up to rounding-level differences.
    EXPECT_NEAR(lo_a[i], lo_b[i], 1e-9);
    EXPECT_NEAR(hi_a[i], hi_b[i], 1e-9);
  }
  // The scope type on its own, with an exception.
  std::fesetround(FE_UPWARD);
  try {
    const RoundToNearestScope scope;
    EXPECT_EQ(std::fegetround(), FE_TONEAREST);
    throw std::runtime_error("x");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(std::fegetround(), FE_UPWARD);
  std::fesetround(FE_TONEAREST);
}

// The tube's bounds x -+ eps enclose the exact values (100 digits). Boost.Interval on the two
// point intervals did not: GCC computed both ends of the one expression once, in the rounding
// mode it set first, and the lower end of x + eps came out rounded up in about 8 % of cases.
TEST(FastInterval, TubeBoundsEncloseTheExactEnds) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> x(-50, 50), e(1e-3, 2);
  for (int it = 0; it < 20000; ++it) {
    const double xk = x(rng), eps = e(rng);
    const abcd::TubeBounds t = abcd::tube_bounds(xk, eps);
    const Big lo = Big(xk) - Big(eps), hi = Big(xk) + Big(eps);
    ASSERT_LE(Big(t.lo.lower()), lo) << it;
    ASSERT_GE(Big(t.lo.upper()), lo) << it;
    ASSERT_LE(Big(t.hi.lower()), hi) << it;
    ASSERT_GE(Big(t.hi.upper()), hi) << it;
  }
}
