// `marsyn check` names a gap no horizon can open (two obstacles closer than 2 (delta + eps)),
// with both obstacles and the width; a field without one gets no warning.
#include <gtest/gtest.h>

#include "run.hpp"

using marsyn::test::run_marsyn;

TEST(ClosedGap, CheckNamesBothObstaclesAndTheWidth) {
  const auto r = run_marsyn(std::string("check ") + MARSYN_SOURCE_DIR + "/tests/continuous/closed_gap.yaml");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("warning: obstacle left_shelf and obstacle right_shelf leave a gap 0.5 wide"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("needs 0.88"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("closed to robot at every horizon"), std::string::npos) << r.out;
}

TEST(ClosedGap, AnOpenFieldHasNoWarning) {
  const auto r = run_marsyn(std::string("check ") + MARSYN_SOURCE_DIR + "/examples/multi_drone.yaml");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.find("leave a gap"), std::string::npos) << r.out;
}
