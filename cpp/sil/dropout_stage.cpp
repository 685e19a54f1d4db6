#include "sil/dropout_stage.hpp"

#include <cmath>

namespace kiloloop::sil {

bool DropoutStage::configure(int n, std::string* why) {
  if (offset_ < 0 || count_ < 1 || offset_ + count_ > n || !std::isfinite(start_) ||
      !std::isfinite(end_) || end_ < start_) {
    *why = "sensor dropout: expected a slice inside y (offset >= 0, count >= 1, offset + count <= " +
           std::to_string(n) + ") and a finite window start <= end";
    return false;
  }
  held_.assign(static_cast<size_t>(count_), 0.0);
  have_ = false;
  return true;
}

void DropoutStage::apply(double t, double* y) noexcept {
  double* slice = y + offset_;
  // A small tolerance on the tick grid: t = k * dt may round just below a window edge.
  const bool inside = t >= start_ - 1e-9 && t < end_ - 1e-9;
  if (inside && have_) {
    for (int i = 0; i < count_; ++i) slice[i] = held_[static_cast<size_t>(i)];
    return;
  }
  // Outside the window (or at its first tick when it opens at the run's start) the slice is
  // the value to hold.
  for (int i = 0; i < count_; ++i) held_[static_cast<size_t>(i)] = slice[i];
  have_ = true;
}

}  // namespace kiloloop::sil
