#pragma once
// Commands already sent but not yet acting on the robot: with a command-to-motor delay of n
// ticks, the last n commands are "in flight". A fixed ring, sized once at configure; push and
// read are allocation-free. oldest(0) is the command acting during the current tick.
#include <vector>

namespace kiloloop {

template <class T>
class InFlight {
 public:
  void configure(int n, const T& fill) {
    buf_.assign(static_cast<size_t>(n > 0 ? n : 0), fill);
    head_ = 0;
  }
  int size() const noexcept { return static_cast<int>(buf_.size()); }
  // j = 0: the oldest (acting now) ... size() - 1: the newest.
  const T& oldest(int j) const noexcept { return buf_[(head_ + static_cast<size_t>(j)) % buf_.size()]; }
  void push(const T& v) noexcept {
    if (buf_.empty()) return;
    buf_[head_] = v;
    head_ = (head_ + 1) % buf_.size();
  }

 private:
  std::vector<T> buf_;
  size_t head_ = 0;
};

}  // namespace kiloloop
