#include "kiloloop/rt/latency_stats.hpp"

#include <gtest/gtest.h>

#include "alloc_counter.hpp"

namespace kiloloop {
namespace {

TEST(LatencyStats, NearestRankSummaryWithoutAllocating) {
  LatencyStats stats(200);
  testing::AllocationScope scope;
  for (int i = 200; i >= 1; --i) stats.record(i);  // 1..200 in reverse order
  const LatencySummary s = stats.summarize();
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_EQ(s.count, 200u);
  EXPECT_EQ(s.median_ns, 100);  // lower middle of an even count
  EXPECT_EQ(s.p99_ns, 198);     // nearest rank: ceil(0.99 * 200) = 198
  EXPECT_EQ(s.max_ns, 200);
  EXPECT_EQ(stats.samples()[0], 200);  // recording order kept
}

TEST(LatencyStats, FullBufferDropsAndCounts) {
  LatencyStats stats(2);
  stats.record(5);
  stats.record(7);
  stats.record(9);
  EXPECT_EQ(stats.size(), 2u);
  EXPECT_EQ(stats.dropped(), 1u);
  EXPECT_EQ(stats.summarize().max_ns, 7);
  stats.clear();
  EXPECT_EQ(stats.summarize().count, 0u);
}

}  // namespace
}  // namespace kiloloop
