#include "kiloloop/status.hpp"

namespace kiloloop {

const char* to_string(Status s) noexcept {
  switch (s) {
    case Status::kOk: return "ok";
    case Status::kSaturated: return "saturated";
    case Status::kReferenceClamped: return "reference_clamped";
    case Status::kIterationLimit: return "iteration_limit";
    case Status::kUnreachable: return "unreachable";
    case Status::kEstimatorDegraded: return "estimator_degraded";
    case Status::kNearSingularity: return "near_singularity";
    case Status::kNonFiniteMeasurement: return "non_finite_measurement";
    case Status::kNonFiniteReference: return "non_finite_reference";
    case Status::kBadSize: return "bad_size";
    case Status::kStaleMeasurement: return "stale_measurement";
    case Status::kNotConfigured: return "not_configured";
    case Status::kInvalidConfig: return "invalid_config";
    case Status::kModelError: return "model_error";
    case Status::kSolverFailed: return "solver_failed";
    case Status::kInfeasible: return "infeasible";
    case Status::kSafeStop: return "safe_stop";
    case Status::kLimitViolation: return "limit_violation";
    case Status::kTorqueOverload: return "torque_overload";
    case Status::kEmergencyStop: return "emergency_stop";
  }
  return "unknown";
}

}  // namespace kiloloop
