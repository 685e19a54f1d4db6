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
  // Indices wrap by a compare, not %: a 64-bit division per access cost ~30 cycles, and the
  // predictor reads every entry of three buffers each tick (10 at 10 ms, 35 at 35 ms).
  const T& oldest(int j) const noexcept {
    size_t i = head_ + static_cast<size_t>(j);
    if (i >= buf_.size()) i -= buf_.size();  // 0 <= j < size()
    return buf_[i];
  }
  void push(const T& v) noexcept {
    if (buf_.empty()) return;
    buf_[head_] = v;
    if (++head_ == buf_.size()) head_ = 0;
  }

 private:
  std::vector<T> buf_;
  size_t head_ = 0;
};

// What accelerations still in flight do over the delay, until the command sent now lands (a
// Smith predictor's model part). Entry j acts during [j, j + 1) ticks from now: its velocity
// change dt a counts fully, its position change for the (n - j - 0.5) ticks left after it.
template <class T>
struct InFlightEffect {
  T velocity;  // sum dt a_j
  T position;  // sum (n - j - 0.5) dt^2 a_j
};

template <class T>
InFlightEffect<T> in_flight_effect(const InFlight<T>& accel, double dt) noexcept {
  InFlightEffect<T> e{T::Zero(), T::Zero()};
  const int n = accel.size();
  for (int j = 0; j < n; ++j) {
    const T& a = accel.oldest(j);
    e.velocity += dt * a;
    e.position += ((n - j - 0.5) * dt * dt) * a;
  }
  return e;
}

}  // namespace kiloloop
