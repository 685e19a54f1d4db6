#include "sil/batch.hpp"

#include <algorithm>
#include <atomic>
#include <thread>

namespace kiloloop::sil {

namespace {
// Each rollout advanced by `ticks` (< 0: to its end) on a pool of threads.
void for_each_rollout(const std::vector<Rollout*>& rollouts, int ticks, int threads) noexcept {
  const int n = static_cast<int>(rollouts.size());
  std::atomic<int> next{0};
  auto worker = [&]() {
    for (int i = next.fetch_add(1); i < n; i = next.fetch_add(1))
      if (ticks < 0) rollouts[i]->run();
      else rollouts[i]->advance(ticks);
  };
  const int count = std::max(1, std::min(threads, n));
  if (count == 1) {
    worker();
    return;
  }
  std::vector<std::thread> pool;
  try {
    pool.reserve(count - 1);
    for (int i = 0; i < count - 1; ++i) pool.emplace_back(worker);
  } catch (...) {
    // No thread could be started (resource limits): the calling thread does the rest alone.
  }
  worker();
  for (auto& t : pool) t.join();
}
}  // namespace

void run_batch(const std::vector<Rollout*>& rollouts, int threads) noexcept {
  for_each_rollout(rollouts, -1, threads);
}

void advance_batch(const std::vector<Rollout*>& rollouts, int ticks, int threads) noexcept {
  for_each_rollout(rollouts, ticks < 0 ? 0 : ticks, threads);
}

}  // namespace kiloloop::sil
