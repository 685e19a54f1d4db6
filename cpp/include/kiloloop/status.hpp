#pragma once
// Signed status codes shared by every configure() and step() in kiloloop.
//   0   ok
//   > 0 degraded but usable: the output is valid, something was limited or clamped
//   < 0 failure: the output is a safe fallback (hold or zero), never NaN
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

}  // namespace kiloloop
