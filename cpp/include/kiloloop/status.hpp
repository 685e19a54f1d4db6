#pragma once
// Signed status codes shared by every configure() and step() in kiloloop.
//   0   ok
//   > 0 degraded but usable: the output is valid, something was limited or clamped
//   < 0 failure: the output is a safe fallback (hold or zero), never NaN
#include <array>
#include <cstdint>

namespace kiloloop {

enum class Status : int {
  kOk = 0,
  // Degraded but usable.
  kSaturated = 1,           // an output was clipped to its limit (effort, thrust, ...)
  kReferenceClamped = 2,    // the reference was outside the joint limits and was clamped
  kIterationLimit = 3,      // an iterative solver stopped at its cap with a usable iterate
  kUnreachable = 4,         // an IK target is out of reach: the last valid solution is kept
  kEstimatorDegraded = 5,   // the state estimate ran without a correction (no stance feet, ...)
  kNearSingularity = 6,     // the arm is close to (or heading into) a singular configuration
  // Failures: the output is the safe fallback.
  kNonFiniteMeasurement = -1,  // NaN/Inf in a measured signal
  kNonFiniteReference = -2,    // NaN/Inf in a reference or command
  kBadSize = -3,               // a vector does not have the size fixed at configure
  kStaleMeasurement = -4,      // the measurement is older than the allowed age
  kNotConfigured = -5,         // step() on an object that was never configured
  kInvalidConfig = -6,         // configure() rejected its settings
  kModelError = -7,            // the model cannot be used for this (e.g. not a serial chain)
  kSolverFailed = -8,          // a numeric solver failed (singular, diverged)
  kInfeasible = -9,            // a constrained problem has no solution
  kSafeStop = -10,             // a safety limit tripped (e.g. trunk tilt): latched safe output
  kLimitViolation = -11,       // a joint position/velocity/acceleration limit tripped a stop
  kTorqueOverload = -12,       // torque overload (sustained I^2 t, or far beyond peak) tripped a stop
  kEmergencyStop = -13,        // the emergency-stop input: controlled stop, then hold
};

inline constexpr bool ok(Status s) noexcept { return static_cast<int>(s) >= 0; }
inline constexpr bool failed(Status s) noexcept { return static_cast<int>(s) < 0; }

// Keeps the more severe of two statuses: any failure beats any degradation beats ok.
inline constexpr Status worst(Status a, Status b) noexcept {
  const int x = static_cast<int>(a), y = static_cast<int>(b);
  if (x < 0 || y < 0) return x < y ? a : b;
  return x > y ? a : b;
}

// A short, stable, lower-case name ("ok", "saturated", ...); never allocates.
const char* to_string(Status s) noexcept;

// The range of Status codes; every enumerator lies in [kMinStatus, kMaxStatus].
inline constexpr int kMinStatus = static_cast<int>(Status::kEmergencyStop);
inline constexpr int kMaxStatus = static_cast<int>(Status::kNearSingularity);

// How many steps returned each Status, since configure (or reset): the one counter struct of
// every controller's step. record() is called once per step with the status the step returned,
// so the counts add up to ticks. A code outside the enum's range is counted in ticks only.
struct StatusCounters {
  std::uint64_t ticks = 0;
  std::array<std::uint64_t, kMaxStatus - kMinStatus + 1> by_status{};  // index: code - kMinStatus

  void record(Status s) noexcept {
    ++ticks;
    const int i = static_cast<int>(s) - kMinStatus;
    if (i >= 0 && i < static_cast<int>(by_status.size())) ++by_status[i];
  }
  std::uint64_t count(Status s) const noexcept {
    const int i = static_cast<int>(s) - kMinStatus;
    return i >= 0 && i < static_cast<int>(by_status.size()) ? by_status[i] : 0;
  }
  // Steps that failed (status < 0) and that were degraded (status > 0).
  std::uint64_t failures() const noexcept {
    std::uint64_t sum = 0;
    for (int c = kMinStatus; c < 0; ++c) sum += by_status[c - kMinStatus];
    return sum;
  }
  std::uint64_t degraded() const noexcept {
    std::uint64_t sum = 0;
    for (int c = 1; c <= kMaxStatus; ++c) sum += by_status[c - kMinStatus];
    return sum;
  }
  void reset() noexcept { *this = StatusCounters{}; }
};

}  // namespace kiloloop
