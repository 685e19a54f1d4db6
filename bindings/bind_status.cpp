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

  // One counter struct for every controller; each status count is also a property named after
  // the status (counters.bad_size, counters.stale_measurement, ...), as the former per-controller
  // structs had them.
  py::class_<StatusCounters> c(m, "StatusCounters", "how many steps returned each Status");
  c.def(py::init<>())
      .def_readonly("ticks", &StatusCounters::ticks)
      .def("count", &StatusCounters::count, py::arg("status"))
      .def_property_readonly("failures", &StatusCounters::failures)
      .def_property_readonly("degraded", &StatusCounters::degraded)
      .def("as_dict", [](const StatusCounters& k) {
        py::dict d;
        for (int code = kMinStatus; code <= kMaxStatus; ++code)
          d[to_string(static_cast<Status>(code))] = k.count(static_cast<Status>(code));
        return d;
      });
  for (int code = kMinStatus; code <= kMaxStatus; ++code) {
    const Status s = static_cast<Status>(code);
    c.def_property_readonly(to_string(s), [s](const StatusCounters& k) { return k.count(s); });
  }
  // Former names.
  m.attr("StepCounters") = c;
  m.attr("CartesianCounters") = c;
}

}  // namespace kiloloop::py_glue
