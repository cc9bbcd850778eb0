// How often one horizon is re-planned for shortfalls between the samples (planning/
// clearance_rounds.hpp): a crowded team's new pair each round keeps the horizon (six rounds), a
// requirement short again after its clearance ends the run at the usual two.
#include <gtest/gtest.h>

#include "marsyn/core/planning/clearance_rounds.hpp"

using marsyn::planning::ClearanceRounds;
using marsyn::planning::RobustCheck;

namespace {

RobustCheck short_for(std::initializer_list<const char*> names) {
  RobustCheck c;
  for (const char* n : names) c.between_shortfalls[n] = {-0.01, 0.1};
  return c;
}

}  // namespace

TEST(ClearanceRounds, ANewPairEachRoundKeepsTheHorizonForSixRounds) {
  ClearanceRounds r;
  const char* pairs[] = {"collision a1 vs a2", "collision a3 vs a4", "collision a5 vs a6",
                         "collision a7 vs a8", "collision a9 vs a10", "collision a11 vs a12", "collision a13 vs a14"};
  for (int i = 0; i < 6; ++i) EXPECT_TRUE(r.take(short_for({pairs[i]}))) << i;  // the old rule stopped at 2
  EXPECT_FALSE(r.take(short_for({pairs[6]})));
  r.reset();  // a longer horizon counts again
  EXPECT_TRUE(r.take(short_for({pairs[6]})));
}

TEST(ClearanceRounds, ARequirementShortAgainEndsTheRunAtTwo) {
  ClearanceRounds r;
  EXPECT_TRUE(r.take(short_for({"collision a1 vs a2"})));
  EXPECT_TRUE(r.take(short_for({"collision a1 vs a2", "collision a3 vs a4"})));  // two, as before
  EXPECT_FALSE(r.take(short_for({"collision a1 vs a2"})));

  ClearanceRounds s;
  EXPECT_TRUE(s.take(short_for({"collision a1 vs a2"})));
  EXPECT_TRUE(s.take(short_for({"collision a3 vs a4"})));
  EXPECT_TRUE(s.take(short_for({"collision a5 vs a6"})));
  EXPECT_FALSE(s.take(short_for({"obstacle p1 vs a7", "collision a3 vs a4"})));  // a3 vs a4 is not closing
}

TEST(ClearanceRounds, TwoPairsShortAtOnceAreACrowdEveryPairKeepsClearanceFor) {
  using marsyn::planning::crowd_clearance;
  RobustCheck c;
  c.between_shortfalls["collision a1 vs a2"] = {-0.02, 0.1, true};
  EXPECT_EQ(crowd_clearance(c), 0.0);  // one pair: its own clearance by name is enough
  c.between_shortfalls["obstacle p1 vs a3"] = {-0.05, 0.1};
  EXPECT_EQ(crowd_clearance(c), 0.0);  // an obstacle is no crowd
  c.between_shortfalls["collision a4 vs a5"] = {-0.01, 0.1, true};
  EXPECT_NEAR(crowd_clearance(c), 0.03, 1e-15);  // 1.5 x the worst pair
}
