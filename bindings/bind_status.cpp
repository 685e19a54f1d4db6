#include "common.hpp"

namespace kiloloop::py_glue {

void bind_status(py::module_& m) {
  py::enum_<Status>(m, "Status", "0 ok, > 0 degraded but usable, < 0 failure (safe fallback output)")
      .value("OK", Status::kOk)
      .value("SATURATED", Status::kSaturated)
      .value("REFERENCE_CLAMPED", Status::kReferenceClamped)
      .value("ITERATION_LIMIT", Status::kIterationLimit)
      .value("UNREACHABLE", Status::kUnreachable)
      .value("ESTIMATOR_DEGRADED", Status::kEstimatorDegraded)
      .value("NEAR_SINGULARITY", Status::kNearSingularity)
      .value("NON_FINITE_MEASUREMENT", Status::kNonFiniteMeasurement)
      .value("NON_FINITE_REFERENCE", Status::kNonFiniteReference)
      .value("BAD_SIZE", Status::kBadSize)
      .value("STALE_MEASUREMENT", Status::kStaleMeasurement)
      .value("NOT_CONFIGURED", Status::kNotConfigured)
      .value("INVALID_CONFIG", Status::kInvalidConfig)
      .value("MODEL_ERROR", Status::kModelError)
      .value("SOLVER_FAILED", Status::kSolverFailed)
      .value("INFEASIBLE", Status::kInfeasible)
      .value("SAFE_STOP", Status::kSafeStop)
      .value("LIMIT_VIOLATION", Status::kLimitViolation)
      .value("TORQUE_OVERLOAD", Status::kTorqueOverload)
      .value("EMERGENCY_STOP", Status::kEmergencyStop)
      .def_property_readonly("ok", [](Status s) { return ok(s); })
      .def_property_readonly("failed", [](Status s) { return failed(s); });
}

}  // namespace kiloloop::py_glue
