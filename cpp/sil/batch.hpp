#pragma once
// Many native rollouts on a pool of C++ threads (MuJoCo's rollout shape): each rollout has its own
// mjData and controller objects, so they share nothing mutable; threads take the next rollout
// index from an atomic counter. Results do not depend on the thread count or on scheduling.
#include <vector>

#include "sil/native_loop.hpp"

namespace kiloloop::sil {

// Runs every rollout to its end on min(threads, rollouts) threads (threads <= 1: the calling
// thread).
void run_batch(const std::vector<Rollout*>& rollouts, int threads) noexcept;
// Runs up to `ticks` more ticks of every rollout (Rollout::advance), the same way: a vectorized
// environment's step.
void advance_batch(const std::vector<Rollout*>& rollouts, int ticks, int threads) noexcept;

}  // namespace kiloloop::sil
