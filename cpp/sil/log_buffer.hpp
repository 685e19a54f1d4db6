#pragma once
// Preallocated per-tick log of the native SIL loop: named channels, sized before the run
// (declare, allocate) so that logging inside the loop is a plain store. Stored as one record per
// tick, every channel side by side (ticks x record_width): a tick's writes are one short run of
// consecutive memory rather than one store stream per channel (a quadruped tick writes about 40
// channels). Python gets each channel gathered into a numpy array of shape (ticks, *shape).
#include <cstddef>
#include <string>
#include <vector>

namespace kiloloop::sil {

struct LogChannel {
  std::string name;
  std::vector<int> shape;  // per-tick shape; {} for a scalar
  int width = 1;           // product of shape
  size_t offset = 0;       // where its row starts in a tick's record
};

class LogBuffer {
 public:
  // Configure time: a channel and its per-tick shape; returns its id.
  int declare(const std::string& name, std::vector<int> shape) {
    LogChannel c;
    c.name = name;
    c.width = 1;
    for (int s : shape) c.width *= s;
    c.shape = std::move(shape);
    c.offset = record_;
    record_ += static_cast<size_t>(c.width);
    channels_.push_back(std::move(c));
    offsets_.push_back(channels_.back().offset);
    return static_cast<int>(channels_.size()) - 1;
  }
  // Zero-filled here, so the loop's first touch of each page is not a page fault.
  void allocate(int ticks) {
    ticks_ = ticks;
    records_.assign(static_cast<size_t>(ticks) * record_, 0.0);
  }
  // The row of channel `id` at tick k (no bounds check: the loop writes ticks < allocate()'s).
  double* row(int id, int k) noexcept {
    return records_.data() + static_cast<size_t>(k) * record_ + offsets_[id];
  }
  const double* row(int id, int k) const noexcept {
    return records_.data() + static_cast<size_t>(k) * record_ + offsets_[id];
  }
  // Channel `id`'s first `ticks` rows, one after the other, into out (ticks x width).
  void copy_channel(int id, int ticks, double* out) const {
    const size_t width = static_cast<size_t>(channels_[id].width);
    for (int k = 0; k < ticks; ++k, out += width) {
      const double* r = row(id, k);
      for (size_t e = 0; e < width; ++e) out[e] = r[e];
    }
  }
  int ticks() const { return ticks_; }
  const std::vector<LogChannel>& channels() const { return channels_; }

 private:
  std::vector<LogChannel> channels_;
  std::vector<size_t> offsets_;  // per channel: its offset (what row() reads, packed)
  std::vector<double> records_;  // ticks x record_
  size_t record_ = 0;            // doubles a tick
  int ticks_ = 0;
};

}  // namespace kiloloop::sil
