#pragma once
// The seeded fuzz harness's shared pieces: a deterministic generator, the pools of bad and extreme
// values, a description of the current input (printed with every failure so that it can be
// replayed: seed + input index), and the per-target tally.
//
// Expectations follow the step contract: every output finite and within the actuator limits
// (always), and a failure status (< 0) for every bad input: NaN/Inf in a used field, a wrong
// size, a stale, future or out-of-order measurement stamp. Extreme but finite values (+-1e308,
// denormals, huge references) carry no status expectation, only the output checks.
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <string>

#include <Eigen/Core>

namespace kiloloop::fuzz {

// splitmix64: tiny, fast, and the same sequence on every platform.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : s_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  int below(int n) { return static_cast<int>(next() % static_cast<std::uint64_t>(n)); }
  bool chance(double p) { return uniform() < p; }

 private:
  std::uint64_t s_;
};

double nonfinite_value(Rng& r);  // NaN, +inf or -inf
double extreme_value(Rng& r);    // finite: +-1e308, +-DBL_MAX, denormals, +-DBL_MIN, +-0, +-1e30

// What was done to the current input, in words (fixed buffer: no allocation per input).
class Desc {
 public:
  void clear() {
    len_ = 0;
    buf_[0] = '\0';
  }
  void add(const char* fmt, ...) __attribute__((format(printf, 2, 3)));
  const char* str() const { return len_ ? buf_ : "(unmodified)"; }

 private:
  char buf_[1024];
  int len_ = 0;
};

// Replaces one random entry of v (n entries) by a non-finite or an extreme value, noting it.
// Returns true when the new value is not finite.
bool poke(Rng& r, double* v, int n, bool nonfinite, Desc& d, const char* name);

struct Tally {
  const char* target = "";
  std::uint64_t inputs = 0;
  std::uint64_t bad_inputs = 0;      // inputs the contract calls bad (a failure status is due)
  std::uint64_t bad_outputs = 0;     // non-finite or beyond-limit outputs, wrong status claims
  std::uint64_t missed_status = 0;   // bad inputs answered with a status >= 0
  std::uint64_t known_failures = 0;  // findings in code this harness may not fix (see report)
  int printed = 0, printed_status = 0, printed_known = 0;
  // Records a finding on input `index` and prints the first few (the input's description).
  void fail(std::uint64_t index, const Desc& d, std::uint64_t* counter, const char* fmt, ...)
      __attribute__((format(printf, 5, 6)));
};

bool all_finite(const double* v, int n);
inline bool all_finite(const Eigen::Ref<const Eigen::MatrixXd>& m) { return m.allFinite(); }

// The staleness and order rule of control/rules.hpp, restated from the spec (not reused) so that a
// controller applying it wrongly is caught.
struct StampModel {
  double max_age = 0.005;
  double newest = 0.0;
  bool has_newest = false;
  bool fresh(double t, double stamp) const {
    if (!std::isfinite(t) || !std::isfinite(stamp)) return false;
    if (!(std::abs(t - stamp) <= max_age)) return false;
    return !has_newest || stamp >= newest;
  }
  void accept(double stamp) {
    newest = stamp;
    has_newest = true;
  }
  void reset() { has_newest = false; }
};

// Time of the next good tick: dt = 1 ms; stamp a little older than t but never older than the
// newest accepted one. After a glitch (an accepted stamp far ahead) the caller resets.
struct Clock {
  double t = 0.0;
  void tick(Rng& r, const StampModel& m, double* t_out, double* stamp_out) {
    t += 0.001;
    double stamp = t - r.uniform(0.0, 0.8 * m.max_age);
    if (m.has_newest && stamp < m.newest && m.newest <= t) stamp = m.newest;
    *t_out = t;
    *stamp_out = stamp;
  }
};

// Time mutations shared by every target; returns a short name of what was done.
void mutate_time(Rng& r, double max_age, const StampModel& m, double* t, double* stamp, Desc& d);

// Targets: each runs `inputs` inputs from `seed`, writing the current index to *progress (the
// parent process reports it if the child crashes).
using TargetFn = Tally (*)(std::uint64_t seed, std::uint64_t inputs, volatile std::uint64_t* progress);
Tally fuzz_qp(std::uint64_t, std::uint64_t, volatile std::uint64_t*);
Tally fuzz_computed_torque(std::uint64_t, std::uint64_t, volatile std::uint64_t*);
Tally fuzz_joint_pd_gravity(std::uint64_t, std::uint64_t, volatile std::uint64_t*);
Tally fuzz_cartesian_impedance(std::uint64_t, std::uint64_t, volatile std::uint64_t*);
Tally fuzz_hybrid_force_position(std::uint64_t, std::uint64_t, volatile std::uint64_t*);
Tally fuzz_cartesian_tracking(std::uint64_t, std::uint64_t, volatile std::uint64_t*);
Tally fuzz_arm_supervisor(std::uint64_t, std::uint64_t, volatile std::uint64_t*);
Tally fuzz_quadruped(std::uint64_t, std::uint64_t, volatile std::uint64_t*);
Tally fuzz_aerial(std::uint64_t, std::uint64_t, volatile std::uint64_t*);

std::string models_dir();

}  // namespace kiloloop::fuzz
