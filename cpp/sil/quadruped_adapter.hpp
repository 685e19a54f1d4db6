#pragma once
// Native SIL adapter of the quadruped family (python/kiloloop/sil/quadruped_family.py builds
// it): maps the measurement and the command onto the QuadrupedController and its torques onto
// the motors, logging the controller's channels.
//   y = [q (12); qd (12); gyro (3); accel (3); quat (4)]   plant joint order (URDF), IMU site
//   u = tau (12)                                           plant joint order
// The controller's joints are leg-major (FL, FR, RL, RR x abd, hip, knee); the rig maps them by
// name: to_ctrl[j] is the plant index of controller joint j.
// ground_truth (debugging: the controller on the simulator's state, QuadrupedInput::
// use_ground_truth) appends 10 entries the rollout reads from qpos / qvel (measurement_source):
//   y = [...34 above...; base position (3) [m]; base quaternion w, x, y, z (4); base linear
//        velocity (3) [m/s], world frame]   the free joint's qpos[0..7), qvel[0..3)
// Commands arrive as kReference events {gait, vx, vy, yaw rate}; foothold offsets (a policy's
// action) are set between chunks of ticks by set_foothold_offset.
#include <array>

#include "kiloloop/quadruped/quadruped_controller.hpp"
#include "sil/adapter.hpp"

namespace kiloloop::sil {

class QuadrupedAdapter final : public Adapter {
 public:
  static constexpr int kJoints = 12;
  static constexpr int kMeasurement = 2 * kJoints + 3 + 3 + 4;
  static constexpr int kGroundTruth = 3 + 4 + 3;  // appended with ground_truth
  // controller: borrowed (the binding keeps its Python object alive); gait, velocity: the command
  // before the first kReference event; ground_truth: y carries the base state (above).
  QuadrupedAdapter(QuadrupedController* controller, const std::array<int, kJoints>& to_ctrl, Gait gait,
                   const Eigen::Vector3d& velocity, bool ground_truth = false);
  int measurement_size() const override { return kMeasurement + (ground_truth_ ? kGroundTruth : 0); }
  int command_size() const override { return kJoints; }
  void declare(LogBuffer& log) override;
  void on_event(const Event& event) noexcept override;
  int step(double t, double stamp, const double* y, double* u, LogBuffer& log, int k) noexcept override;
  IoRecordBytes io_record_bytes() const override { return sil::io_record_bytes(in_, out_); }
  void write_io_record(const IoRecordBytes& sizes, unsigned char* p) const noexcept override {
    sil::write_io_record(in_, out_, sizes, p);
  }
  // [m] per foot, trunk frame (QuadrupedInput::foothold_offset), from the next tick on.
  void set_foothold_offset(const Vector12d& offset) noexcept { in_.foothold_offset = offset; }

 private:
  QuadrupedController* c_;
  std::array<int, kJoints> to_ctrl_;
  bool ground_truth_ = false;
  QuadrupedInput in_;
  QuadrupedOutput out_;
  int ch_status_ = 0, ch_est_pos_ = 0, ch_est_vel_ = 0, ch_est_quat_ = 0, ch_tilt_ = 0, ch_safe_stop_ = 0, ch_contact_ = 0,
      ch_scheduled_ = 0, ch_clearance_ = 0, ch_tau_ = 0, ch_force_cmd_ = 0, ch_v_cmd_ = 0, ch_qp_ = 0;
};

}  // namespace kiloloop::sil
