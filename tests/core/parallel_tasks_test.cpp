// The core's one work queue (core/parallel_tasks.hpp), which tracking, verification and the
// controller reader share: every task runs once, and a failure is reported the same way whatever
// the threads' timing.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "marsyn/core/parallel_tasks.hpp"

using marsyn::parallel_tasks;

TEST(ParallelTasks, EveryTaskRunsExactlyOnce) {
  for (int threads : {1, 2, 3, 16}) {
    std::vector<std::atomic<int>> ran(257);
    parallel_tasks(257, threads, [&](int i) { ++ran[static_cast<size_t>(i)]; });
    for (size_t i = 0; i < ran.size(); ++i) EXPECT_EQ(ran[i].load(), 1) << "task " << i << ", " << threads << " threads";
  }
  int calls = 0;
  parallel_tasks(0, 4, [&](int) { ++calls; });
  EXPECT_EQ(calls, 0);
}

TEST(ParallelTasks, TheLowestFailingTaskIsReportedAndEveryLowerOneEnds) {
  for (int attempt = 0; attempt < 20; ++attempt) {
    std::vector<std::atomic<int>> ran(64);
    try {
      parallel_tasks(64, 4, [&](int i) {
        // Task 40 fails at once; task 30 fails late: the report must still name 30.
        if (i == 40) throw std::runtime_error("task 40");
        if (i == 30) {
          std::this_thread::sleep_for(std::chrono::milliseconds(2));
          throw std::runtime_error("task 30");
        }
        ++ran[static_cast<size_t>(i)];
      });
      FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), "task 30");
    }
    for (int i = 0; i < 30; ++i) EXPECT_EQ(ran[static_cast<size_t>(i)].load(), 1) << "task " << i;
  }
}
