#pragma once
// Counts heap allocations in the current process: a malloc-level interposer (malloc, calloc,
// realloc, aligned_alloc, posix_memalign, memalign) plus a counting global operator new. Under
// AddressSanitizer, which owns the allocator, ASan's malloc hook counts instead (same coverage,
// nothing interposed). Linked only into test and benchmark executables, never into the library.
//
//   kiloloop::testing::AllocationScope scope;   // starts counting
//   ... code under test ...
//   EXPECT_EQ(scope.count(), 0u);
#include <cstddef>

namespace kiloloop::testing {

// Allocations seen since the process started (counting is always on; scopes take differences).
std::size_t allocation_count() noexcept;
// True when the count comes from the sanitizer's allocation hook (an ASan build).
bool allocation_counter_uses_sanitizer_hook() noexcept;

class AllocationScope {
 public:
  AllocationScope() noexcept : start_(allocation_count()) {}
  std::size_t count() const noexcept { return allocation_count() - start_; }

 private:
  std::size_t start_;
};

}  // namespace kiloloop::testing
