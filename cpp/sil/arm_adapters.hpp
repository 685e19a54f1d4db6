#pragma once
// Native SIL adapters of the arm family, built by the references of python/kiloloop/sil/
// arm_adapters.py (JointTracking, CartesianTracking, Supervised): each maps y = [q; qd] and its
// reference onto one controller and logs its signals.
// The controllers and references are the ones the Python side configured (borrowed pointers:
// the binding keeps their Python objects alive for the adapter's lifetime).
#include <variant>

#include <Eigen/Core>

#include "kiloloop/arm/cartesian_tracking.hpp"
#include "kiloloop/control/joint_torque_controller.hpp"
#include "kiloloop/safety/arm_supervisor.hpp"
#include "kiloloop/trajectory/cartesian_line.hpp"
#include "kiloloop/trajectory/quintic.hpp"
#include "kiloloop/trajectory/trapezoid.hpp"
#include "sil/adapter.hpp"

namespace kiloloop::sil {

// A joint-space reference: either trajectory type (same sample() signature, no common base).
using JointReference = std::variant<const QuinticTrajectory*, const TrapezoidTrajectory*>;

// Writes q_ref, qd_ref, qdd_ref at t plus the current reference offset (zero until a kReference
// event sets one).
class JointReferenceSampler {
 public:
  void configure(JointReference reference, int nq);
  void sample(double t, JointControlInput& in) const noexcept;
  void set_offset(const Event& event) noexcept;

 private:
  JointReference reference_{};
  Eigen::VectorXd offset_;  // (nq) [rad]
  bool has_offset_ = false;
};

// q, qd -> joint torque controller (computed torque or PD + gravity) on a joint trajectory.
// Logs q, qd, q_ref, tau, status.
class JointTrackingAdapter final : public Adapter {
 public:
  JointTrackingAdapter(JointTorqueController* controller, JointReference reference);
  int measurement_size() const override { return 2 * nq_; }
  int command_size() const override { return nq_; }
  void declare(LogBuffer& log) override;
  void on_event(const Event& event) noexcept override;
  int step(double t, double stamp, const double* y, double* u, LogBuffer& log, int k) noexcept override;
  IoRecordBytes io_record_bytes() const override { return sil::io_record_bytes(in_, out_); }
  void write_io_record(const IoRecordBytes& sizes, unsigned char* p) const noexcept override {
    sil::write_io_record(in_, out_, sizes, p);
  }

 private:
  JointTorqueController* c_;
  int nq_;
  JointReferenceSampler ref_;
  JointControlInput in_;
  JointControlOutput out_;
  int ch_q_ = 0, ch_qd_ = 0, ch_q_ref_ = 0, ch_tau_ = 0, ch_status_ = 0;
};

// q, qd -> Cartesian tracking (differential IK + computed torque) on a CartesianLine.
// Logs q, q_ref, tau, pose_ref (4 x 4), ik_error (6), status.
class CartesianTrackingAdapter final : public Adapter {
 public:
  CartesianTrackingAdapter(CartesianTrackingController* controller, const CartesianLine* line);
  int measurement_size() const override { return 2 * nq_; }
  int command_size() const override { return nq_; }
  void declare(LogBuffer& log) override;
  void on_event(const Event& event) noexcept override;
  int step(double t, double stamp, const double* y, double* u, LogBuffer& log, int k) noexcept override;

 private:
  CartesianTrackingController* c_;
  const CartesianLine* line_;
  int nq_;
  Eigen::Vector3d offset_ = Eigen::Vector3d::Zero();  // [m] kReference position offset
  bool has_offset_ = false;  // adding a zero offset would turn -0.0 into +0.0: only once set
  CartesianTrackingInput in_;
  CartesianTrackingOutput out_;
  int ch_q_ = 0, ch_q_ref_ = 0, ch_tau_ = 0, ch_pose_ref_ = 0, ch_ik_error_ = 0, ch_status_ = 0;
};

// q, qd -> joint torque controller -> ArmSupervisor (e-stop from kEstop events) -> motors.
// Logs q, qd, q_ref, tau (the supervisor's), mode, status, manipulability.
class SupervisedAdapter final : public Adapter {
 public:
  SupervisedAdapter(JointTorqueController* controller, ArmSupervisor* supervisor,
                    JointReference reference);
  int measurement_size() const override { return 2 * nq_; }
  int command_size() const override { return nq_; }
  void declare(LogBuffer& log) override;
  void on_event(const Event& event) noexcept override;
  int step(double t, double stamp, const double* y, double* u, LogBuffer& log, int k) noexcept override;
  IoRecordBytes io_record_bytes() const override { return sil::io_record_bytes(cin_, cout_); }
  void write_io_record(const IoRecordBytes& sizes, unsigned char* p) const noexcept override {
    sil::write_io_record(cin_, cout_, sizes, p);
  }

 private:
  JointTorqueController* c_;
  ArmSupervisor* s_;
  int nq_;
  JointReferenceSampler ref_;
  JointControlInput cin_;
  JointControlOutput cout_;
  SupervisorInput sin_;
  SupervisorOutput sout_;
  bool estop_ = false;
  int ch_q_ = 0, ch_qd_ = 0, ch_q_ref_ = 0, ch_tau_ = 0, ch_mode_ = 0, ch_status_ = 0,
      ch_manip_ = 0;
};

}  // namespace kiloloop::sil
