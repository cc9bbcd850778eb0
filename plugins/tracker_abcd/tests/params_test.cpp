// abcd's parameters, declared once on abcd::Options (abcd_tracker.cpp): the listing, where
// each value lands in the options the sweep reads, and the order and words of the refusals.
#include <gtest/gtest.h>

#include <string>

#include "abcd_tracker.hpp"

using namespace marsyn;
using namespace marsyn::abcd;

TEST(AbcdParams, ListedDefaultsAreTheOptionsTheSweepReads) {
  const auto specs = AbcdTracker::param_specs();
  const Options s = AbcdTracker().options_for(TrackOptions{});
  auto listed = [&](const std::string& name) {
    for (const auto& p : specs)
      if (p.name == name) return p.default_value;
    return std::string("(not listed)");
  };
  EXPECT_EQ(listed("substeps"), std::to_string(s.successor.substeps));
  EXPECT_EQ(listed("taylor_terms"), std::to_string(s.successor.taylor_terms));
  EXPECT_EQ(listed("picard_iterations"), std::to_string(s.successor.picard_iterations));
  EXPECT_EQ(listed("prefilter"), s.prefilter ? "true" : "false");
  EXPECT_EQ(listed("prefilter_substeps"), std::to_string(s.prefilter_substeps));
  EXPECT_EQ(listed("threads"), "0");
  EXPECT_EQ(listed("enclosure_substeps"), std::to_string(s.enclosure_substeps));
  EXPECT_EQ(listed("enclosure_block"), std::to_string(s.enclosure_block));
}

TEST(AbcdParams, EachValueLandsWhereTheSweepReadsIt) {
  Params p;
  p.set("substeps", 5L);
  p.set("taylor_terms", 7L);
  p.set("picard_iterations", 3L);
  p.set("prefilter", false);
  p.set("prefilter_substeps", 6L);
  p.set("enclosure_substeps", 9L);
  p.set("enclosure_block", 11L);
  TrackOptions run;
  run.threads = 4;
  const Options s = AbcdTracker(p).options_for(run);
  EXPECT_EQ(s.successor.substeps, 5);
  EXPECT_EQ(s.successor.taylor_terms, 7);
  EXPECT_EQ(s.successor.picard_iterations, 3);
  EXPECT_FALSE(s.prefilter);
  EXPECT_EQ(s.prefilter_substeps, 6);
  EXPECT_EQ(s.enclosure_substeps, 9);
  EXPECT_EQ(s.enclosure_block, 11);
  EXPECT_EQ(s.threads, 4);  // threads 0: the run's
  p.set("threads", 3L);
  EXPECT_EQ(AbcdTracker(p).options_for(run).threads, 3);
}

TEST(AbcdParams, EnclosureRangesAreReportedBeforeTheOthers) {
  Params p;
  p.set("substeps", 0L);
  p.set("enclosure_block", 0L);
  try {
    AbcdTracker t(p);
    FAIL() << "accepted substeps 0 and enclosure_block 0";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.field(), "enclosure_block");
    EXPECT_STREQ(e.what(), "expected an integer in [1, 64]");
  }
  Params q;
  q.set("substeps", 0L);
  try {
    AbcdTracker t(q);
    FAIL() << "accepted substeps 0";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.field(), "substeps");
    EXPECT_STREQ(e.what(), "expected an integer in [1, 1000]");
  }
}
