#include "alloc_counter.hpp"

#include <cstdlib>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

// The zero-allocation tests are only worth something if the counter sees allocations.
TEST(AllocCounter, SeesNewMallocAndVectorGrowth) {
  kiloloop::testing::AllocationScope scope;
  auto p = std::make_unique<int>(3);
  void* volatile raw = std::malloc(16);  // volatile: the compiler may not elide the pair
  std::free(raw);
  std::vector<double> v(100);
  EXPECT_GE(scope.count(), 3u) << (kiloloop::testing::allocation_counter_uses_sanitizer_hook()
                                       ? "counting through the ASan malloc hook"
                                       : "counting through the malloc interposer");
}

TEST(AllocCounter, QuietCodeCountsZero) {
  kiloloop::testing::AllocationScope scope;
  double s = 0;
  for (int i = 0; i < 1000; ++i) s += i * 0.5;
  EXPECT_EQ(scope.count(), 0u) << s;
}
