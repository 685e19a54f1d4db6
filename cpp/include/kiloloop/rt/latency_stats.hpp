#pragma once
// LatencyStats: per-tick latency samples [ns] in buffers sized once, summarized as median, p99 and
// max. record() and summarize() never allocate, so a 1 kHz loop can keep statistics as it runs.
// Percentiles are nearest-rank (the median of an even count is the lower middle sample).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace kiloloop {

struct LatencySummary {
  std::int64_t median_ns = 0;
  std::int64_t p99_ns = 0;
  std::int64_t max_ns = 0;
  std::size_t count = 0;  // samples summarized
};

class LatencyStats {
 public:
  explicit LatencyStats(std::size_t capacity = 0);  // allocates: call at configure time

  // Stores one sample; once full, further samples are dropped and counted.
  void record(std::int64_t ns) noexcept {
    if (size_ < samples_.size()) samples_[size_++] = ns;
    else ++dropped_;
  }
  void clear() noexcept { size_ = dropped_ = 0; }

  std::size_t size() const { return size_; }
  std::size_t capacity() const { return samples_.size(); }
  std::size_t dropped() const { return dropped_; }
  const std::int64_t* samples() const { return samples_.data(); }  // in recording order

  // Sorts a scratch copy partially (samples keep their order); all zero when empty.
  LatencySummary summarize() noexcept;

 private:
  std::vector<std::int64_t> samples_, scratch_;
  std::size_t size_ = 0, dropped_ = 0;
};

}  // namespace kiloloop
