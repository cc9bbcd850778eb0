// Agents to MPI ranks (rank_fanout.hpp): the rule a user reads in docs/mpi.md.
#include <gtest/gtest.h>

#include "marsyn/core/tracking/rank_fanout.hpp"

using marsyn::assign_agents_to_ranks;

TEST(RankAssignment, OneRankTracksEverythingItself) {
  const auto a = assign_agents_to_ranks({5, 1, 1}, 1);
  EXPECT_TRUE(a.split.empty());
  EXPECT_EQ(a.rank_of, (std::vector<int>{0, 0, 0}));
}

TEST(RankAssignment, AnAgentHeavierThanAFairShareIsSplitOverAllRanks) {
  // The crane beside a vehicle: the crane alone is more than half of the work.
  const auto a = assign_agents_to_ranks({100, 0.1}, 2);
  EXPECT_EQ(a.split, (std::vector<int>{0}));
  EXPECT_EQ(a.rank_of, (std::vector<int>{-1, 0}));
}

TEST(RankAssignment, LargestFirstToTheLeastLoadedRank) {
  // 4 + 3 + 2 + 2 + 1 over 2 ranks: 4 -> r0, 3 -> r1, 2 -> r1 (5), 2 -> r0 (6), 1 -> r1 (6).
  const auto a = assign_agents_to_ranks({2, 4, 1, 3, 2}, 2);
  EXPECT_TRUE(a.split.empty());
  EXPECT_EQ(a.rank_of, (std::vector<int>{1, 0, 1, 1, 0}));
}

TEST(RankAssignment, EqualAgentsSpreadEvenly) {
  const auto a = assign_agents_to_ranks(std::vector<double>(10, 1.0), 3);
  std::vector<int> count(3, 0);
  for (int r : a.rank_of) ++count[static_cast<size_t>(r)];
  EXPECT_EQ(count, (std::vector<int>{4, 3, 3}));
}

TEST(RankAssignment, MoreRanksThanAgentsSplitsEveryAgent) {
  const auto a = assign_agents_to_ranks({1, 1}, 4);
  EXPECT_EQ(a.split, (std::vector<int>{0, 1}));
}

TEST(RankAssignment, AgentsWithoutAnEstimateStillSpread) {
  const auto a = assign_agents_to_ranks({0, 0, 0, 0}, 2);
  EXPECT_TRUE(a.split.empty());
  EXPECT_EQ(a.rank_of, (std::vector<int>{0, 1, 0, 1}));
}
