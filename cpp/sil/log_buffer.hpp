#pragma once
// Preallocated per-tick log of the native SIL loop: named channels, each (ticks x width) doubles,
// sized before the run (declare) so that logging inside the loop is a plain store. Python gets
// each channel as a numpy array of shape (ticks, *shape).
#include <string>
#include <vector>

namespace kiloloop::sil {

struct LogChannel {
  std::string name;
  std::vector<int> shape;     // per-tick shape; {} for a scalar
  int width = 1;              // product of shape
  std::vector<double> data;   // (ticks x width), row-major
};

class LogBuffer {
 public:
  LogBuffer() = default;
  // Movable (a vector's move keeps its buffer, so the slots stay valid), not copyable: a copy's
  // slots would point into the original's buffers.
  LogBuffer(LogBuffer&&) = default;
  LogBuffer& operator=(LogBuffer&&) = default;
  LogBuffer(const LogBuffer&) = delete;
  LogBuffer& operator=(const LogBuffer&) = delete;
  // Configure time: a channel and its per-tick shape; returns its id.
  int declare(const std::string& name, std::vector<int> shape) {
    LogChannel c;
    c.name = name;
    c.width = 1;
    for (int s : shape) c.width *= s;
    c.shape = std::move(shape);
    channels_.push_back(std::move(c));
    return static_cast<int>(channels_.size()) - 1;
  }
  void allocate(int ticks) {
    ticks_ = ticks;
    slots_.clear();
    for (auto& c : channels_) {
      c.data.assign(static_cast<size_t>(ticks) * c.width, 0.0);
      slots_.push_back({c.data.data(), static_cast<size_t>(c.width)});
    }
  }
  // The row of channel `id` at tick k (no bounds check: the loop writes ticks < allocate()'s).
  double* row(int id, int k) noexcept {
    const Slot& s = slots_[id];
    return s.data + static_cast<size_t>(k) * s.width;
  }
  int ticks() const { return ticks_; }
  const std::vector<LogChannel>& channels() const { return channels_; }
  std::vector<LogChannel>& channels() { return channels_; }

 private:
  // Per channel, what row() reads, packed (16 bytes a channel instead of a whole LogChannel with
  // its name and shape): a tick's log writes touch a few cache lines of bookkeeping, not one per
  // channel. Set by allocate(); the data buffers do not move afterwards.
  struct Slot {
    double* data;
    size_t width;
  };
  std::vector<LogChannel> channels_;
  std::vector<Slot> slots_;
  int ticks_ = 0;
};

}  // namespace kiloloop::sil
