// Memory stage by stage (issue 50 item 4): a stage's peak is its own, not the process's record
// set by an earlier stage, even one between two samples (it raised the high-water mark), and what
// it added is measured from its start.
#include <gtest/gtest.h>

#include <memory>

#include "marsyn/core/stage_memory.hpp"

namespace {

constexpr double kMiB = 1048576.0;

// 64 MiB, every page written so that it is resident.
void touch_64_mib() {
  const std::size_t n = 64u << 20;
  std::unique_ptr<char[]> block(new char[n]);
  // Through a volatile pointer: an allocation only written to may be elided.
  volatile char* page = block.get();
  for (std::size_t i = 0; i < n; i += 4096) page[i] = 1;
}

TEST(StageMemory, EachStageSeesItsOwnPeakNotAnEarlierOnes) {
  marsyn::StageMemory m;
  {
    const marsyn::StageWatch w(m.plan);
    touch_64_mib();
  }
  { const marsyn::StageWatch w(m.verify); }  // allocates nothing of its own
  EXPECT_GE(m.plan.added_bytes(), 60 * kMiB);
  EXPECT_LE(m.plan.added_bytes(), 80 * kMiB);  // the sanitizers' shadow of the block too
  // Read from the high-water mark alone, the verification's peak would be the plan's, 64 MiB above
  // its start.
  EXPECT_LT(m.verify.added_bytes(), 8 * kMiB);
  const std::string text = marsyn::stage_memory_text(m);
  EXPECT_EQ(text.rfind("plan ", 0), 0u) << text;
  EXPECT_NE(text.find(", verification "), std::string::npos) << text;
  EXPECT_EQ(text.find("tracking"), std::string::npos) << text;  // not run: not named
}

TEST(StageMemory, ARoundAfterTheFirstKeepsTheLargerPeakAndTheFirstStart) {
  marsyn::StagePeak track;
  { const marsyn::StageWatch w(track); touch_64_mib(); }
  const double first_start = track.start_bytes, first_peak = track.peak_bytes;
  { const marsyn::StageWatch w(track); }
  EXPECT_EQ(track.start_bytes, first_start);
  EXPECT_GE(track.peak_bytes, first_peak);  // the larger kept (the sanitizers' quarantine may raise it)
}

}  // namespace
