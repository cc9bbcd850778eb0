// The period enclosures' one file encoding (marsyn/period_enclosure_file.hpp), which both trackers'
// controller files use: what is written reads back bit for bit, and a file whose enclosures could
// not be the controller's promise (a step outside the horizon, t0 > t1, an inverted or NaN box, a
// count the payload cannot hold) is refused with a message saying which.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "marsyn/period_enclosure_file.hpp"

namespace {

using marsyn::PeriodEnclosure;

PeriodEnclosure enclosure(int step, int n) {
  PeriodEnclosure e;
  e.step = step;
  e.t0 = 0.1 * step;
  e.t1 = 0.1 * step + 0.05;
  e.state = {Eigen::VectorXd::LinSpaced(n, -1.0, 0.5), Eigen::VectorXd::LinSpaced(n, 1.0 / 3.0, 2.0)};
  e.workspace = {e.state.lo.head(2), e.state.hi.head(2)};
  return e;
}

std::string encode(const std::vector<PeriodEnclosure>& es, int n) {
  marsyn::binary::Writer w;
  marsyn::binary::write_period_enclosures(w, es, n);
  return w.bytes();
}

std::vector<PeriodEnclosure> decode(const std::string& bytes, int n, int steps) {
  marsyn::binary::Reader r(bytes, 0, bytes.size(), "controller file x.ctrl");
  auto out = marsyn::binary::read_period_enclosures(r, n, steps);
  if (!r.done()) throw std::runtime_error("trailing bytes");
  return out;
}

std::string refusal(const std::string& bytes, int n, int steps) {
  try {
    decode(bytes, n, steps);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(PeriodEnclosureFile, RoundTripIsExact) {
  const int n = 3;
  const std::vector<PeriodEnclosure> es{enclosure(0, n), enclosure(1, n), enclosure(1, n), enclosure(4, n)};
  const auto back = decode(encode(es, n), n, 5);
  ASSERT_EQ(back.size(), es.size());
  for (size_t q = 0; q < es.size(); ++q) {
    EXPECT_EQ(back[q].step, es[q].step);
    EXPECT_EQ(back[q].t0, es[q].t0);
    EXPECT_EQ(back[q].t1, es[q].t1);
    EXPECT_EQ(back[q].state.lo, es[q].state.lo);
    EXPECT_EQ(back[q].state.hi, es[q].state.hi);
    EXPECT_EQ(back[q].workspace.lo, es[q].workspace.lo);
    EXPECT_EQ(back[q].workspace.hi, es[q].workspace.hi);
  }
  EXPECT_TRUE(decode(encode({}, n), n, 5).empty());
}

TEST(PeriodEnclosureFile, EnclosuresThatCannotBeAPromiseAreRefused) {
  const int n = 2;
  EXPECT_EQ(refusal(encode({enclosure(5, n)}, n), n, 5),
            "controller file x.ctrl: period enclosure for a step outside the horizon");
  EXPECT_EQ(refusal(encode({enclosure(4, n)}, n), n, 5), "");  // the last step is inside
  PeriodEnclosure late = enclosure(1, n);
  std::swap(late.t0, late.t1);
  EXPECT_EQ(refusal(encode({late}, n), n, 5), "controller file x.ctrl: bad period enclosure (t0 > t1)");
  PeriodEnclosure inverted = enclosure(1, n);
  inverted.state.lo[1] = inverted.state.hi[1] + 1e-12;
  EXPECT_EQ(refusal(encode({inverted}, n), n, 5), "controller file x.ctrl: bad period enclosure (an inverted or NaN box)");
  PeriodEnclosure nan_workspace = enclosure(1, n);
  nan_workspace.workspace.hi[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(refusal(encode({nan_workspace}, n), n, 5),
            "controller file x.ctrl: bad period enclosure (an inverted or NaN box)");
  // A count of 2^32 - 1 with one record behind it: refused before any allocation.
  std::string huge = encode({enclosure(0, n)}, n);
  for (int b = 0; b < 4; ++b) huge[b] = '\xff';
  EXPECT_EQ(refusal(huge, n, 5), "controller file x.ctrl: truncated payload");
}

}  // namespace
