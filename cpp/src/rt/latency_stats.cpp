#include "kiloloop/rt/latency_stats.hpp"

#include <algorithm>
#include <cmath>

namespace kiloloop {

LatencyStats::LatencyStats(std::size_t capacity) : samples_(capacity), scratch_(capacity) {}

LatencySummary LatencyStats::summarize() noexcept {
  LatencySummary s;
  s.count = size_;
  if (size_ == 0) return s;
  // Nearest rank: the smallest sample with at least p of all samples at or below it.
  const auto rank = [n = size_](double p) {
    const auto k = static_cast<std::size_t>(std::ceil(p * static_cast<double>(n)));
    return std::min(std::max<std::size_t>(k, 1), n) - 1;
  };
  const auto first = scratch_.begin(), last = first + static_cast<std::ptrdiff_t>(size_);
  std::copy(samples_.begin(), samples_.begin() + static_cast<std::ptrdiff_t>(size_), first);
  // nth_element partitions around p99, so the median lies left of it and the max right of it.
  const auto p99 = first + static_cast<std::ptrdiff_t>(rank(0.99));
  std::nth_element(first, p99, last);
  const auto median = first + static_cast<std::ptrdiff_t>(rank(0.5));
  std::nth_element(first, median, p99);
  s.p99_ns = *p99;
  s.median_ns = *median;
  s.max_ns = *std::max_element(p99, last);
  return s;
}

}  // namespace kiloloop
