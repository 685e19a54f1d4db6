#pragma once
// The fixed-rate loop: absolute 1 ms deadlines on CLOCK_MONOTONIC (clock_nanosleep with
// TIMER_ABSTIME, so one late tick does not shift the next), SCHED_FIFO and mlockall when the
// process may use them (else it runs as an ordinary process and says so). Per tick it records the
// wake-up latency (deadline -> awake) and the step time (awake -> output written) and counts
// deadline overruns (output written after the next deadline). Nothing in the loop allocates.
#include <sched.h>
#include <sys/mman.h>
#include <time.h>

#include <array>
#include <cstdint>
#include <cstdio>

#include "kiloloop/rt/latency_stats.hpp"

namespace firmware {

constexpr std::int64_t kPeriodNs = 1'000'000;  // [ns] 1 kHz

struct RealtimeSetup {
  bool locked = false;  // mlockall: no page faults in the loop
  bool fifo = false;    // SCHED_FIFO priority 80
};

inline RealtimeSetup enter_realtime() {
  RealtimeSetup s;
  s.locked = mlockall(MCL_CURRENT | MCL_FUTURE) == 0;
  sched_param p{};
  p.sched_priority = 80;
  s.fifo = sched_setscheduler(0, SCHED_FIFO, &p) == 0;
  return s;
}

inline std::int64_t now_ns() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

// Wake-up latency histogram, bins in microseconds.
class LatencyHistogram {
 public:
  static constexpr std::array<std::int64_t, 9> kUpperUs{5, 10, 20, 50, 100, 200, 500, 1000, 5000};
  void add(std::int64_t ns) noexcept {
    std::size_t b = 0;
    while (b < kUpperUs.size() && ns >= kUpperUs[b] * 1000) ++b;
    ++counts_[b];
  }
  void print(const char* title) const {
    std::printf("%s\n", title);
    std::int64_t lower = 0;
    for (std::size_t b = 0; b <= kUpperUs.size(); ++b) {
      if (b < kUpperUs.size())
        std::printf("  %5lld .. %5lld us  %8ld\n", (long long)lower, (long long)kUpperUs[b], counts_[b]);
      else
        std::printf("  %5lld us ..         %8ld\n", (long long)lower, counts_[b]);
      if (b < kUpperUs.size()) lower = kUpperUs[b];
    }
  }

 private:
  std::array<long, kUpperUs.size() + 1> counts_{};
};

struct LoopReport {
  long ticks = 0, overruns = 0;
  kiloloop::LatencySummary wake, step;
  LatencyHistogram histogram;
};

// Runs `ticks` ticks of tick() on absolute 1 ms deadlines.
template <class Tick>
LoopReport run_fixed_rate(long ticks, Tick&& tick) {
  LoopReport r;
  kiloloop::LatencyStats wake(static_cast<std::size_t>(ticks)), step(static_cast<std::size_t>(ticks));
  timespec deadline;
  clock_gettime(CLOCK_MONOTONIC, &deadline);
  for (long k = 0; k < ticks; ++k) {
    deadline.tv_nsec += kPeriodNs;
    if (deadline.tv_nsec >= 1'000'000'000) {
      deadline.tv_nsec -= 1'000'000'000;
      ++deadline.tv_sec;
    }
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) != 0) {
    }
    const std::int64_t due = std::int64_t(deadline.tv_sec) * 1'000'000'000 + deadline.tv_nsec;
    const std::int64_t awake = now_ns();
    tick();
    const std::int64_t done = now_ns();
    wake.record(awake - due);
    step.record(done - awake);
    r.histogram.add(awake - due);
    if (done > due + kPeriodNs) ++r.overruns;
    ++r.ticks;
  }
  r.wake = wake.summarize();
  r.step = step.summarize();
  return r;
}

}  // namespace firmware
