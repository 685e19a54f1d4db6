#include "sil/quadruped_adapter.hpp"

#include <algorithm>

namespace kiloloop::sil {

namespace {
template <class V>
void store(const V& v, double* row) noexcept { std::copy(v.data(), v.data() + v.size(), row); }
}  // namespace

QuadrupedAdapter::QuadrupedAdapter(QuadrupedController* controller, const std::array<int, kJoints>& to_ctrl,
                                   Gait gait, const Eigen::Vector3d& velocity, bool ground_truth)
    : c_(controller), to_ctrl_(to_ctrl), ground_truth_(ground_truth) {
  in_.gait = gait;
  in_.velocity_command = velocity;
  in_.use_ground_truth = ground_truth;
}

void QuadrupedAdapter::declare(LogBuffer& log) {
  // The channels (and shapes) QuadrupedRig._record writes.
  ch_status_ = log.declare("status", {});
  ch_est_pos_ = log.declare("est_pos", {3});
  ch_est_vel_ = log.declare("est_vel", {3});
  ch_est_quat_ = log.declare("est_quat", {4});  // the controller's orientation estimate (w, x, y, z)
  ch_tilt_ = log.declare("tilt", {});
  ch_safe_stop_ = log.declare("safe_stop", {});
  ch_contact_ = log.declare("contact", {4});
  ch_scheduled_ = log.declare("scheduled", {4});
  ch_clearance_ = log.declare("foot_clearance", {4});
  ch_tau_ = log.declare("tau", {kJoints});
  ch_force_cmd_ = log.declare("foot_force_cmd", {kJoints});
  ch_v_cmd_ = log.declare("v_cmd", {3});
  ch_qp_ = log.declare("qp_iterations", {});
}

void QuadrupedAdapter::on_event(const Event& event) noexcept {
  if (event.kind != EventKind::kReference || event.payload.size() != 4) return;
  in_.gait = event.payload[0] != 0.0 ? Gait::kTrot : Gait::kStand;
  in_.velocity_command = Eigen::Vector3d(event.payload[1], event.payload[2], event.payload[3]);
}

int QuadrupedAdapter::step(double t, double stamp, const double* y, double* u, LogBuffer& log, int k) noexcept {
  in_.t = t;
  in_.stamp = stamp;
  for (int j = 0; j < kJoints; ++j) {
    in_.q[j] = y[to_ctrl_[j]];
    in_.qd[j] = y[kJoints + to_ctrl_[j]];
  }
  const double* imu = y + 2 * kJoints;
  in_.gyro = Eigen::Vector3d(imu[0], imu[1], imu[2]);
  in_.accel = Eigen::Vector3d(imu[3], imu[4], imu[5]);
  in_.quat = Eigen::Vector4d(imu[6], imu[7], imu[8], imu[9]);
  if (ground_truth_) {  // the simulator's base state, as QuadrupedRig._loop hands it over
    const double* truth = y + kMeasurement;
    in_.true_position = Eigen::Vector3d(truth[0], truth[1], truth[2]);
    in_.true_quat = Eigen::Vector4d(truth[3], truth[4], truth[5], truth[6]);
    in_.true_velocity = Eigen::Vector3d(truth[7], truth[8], truth[9]);
  }
  const int status = static_cast<int>(c_->step(in_, out_));
  *log.row(ch_status_, k) = status;
  store(out_.position, log.row(ch_est_pos_, k));
  store(out_.velocity, log.row(ch_est_vel_, k));
  store(out_.quat, log.row(ch_est_quat_, k));
  *log.row(ch_tilt_, k) = out_.tilt;
  *log.row(ch_safe_stop_, k) = out_.safe_stop ? 1.0 : 0.0;
  store(out_.contact, log.row(ch_contact_, k));
  store(out_.scheduled, log.row(ch_scheduled_, k));
  store(out_.foot_clearance, log.row(ch_clearance_, k));
  store(out_.tau, log.row(ch_tau_, k));
  store(out_.foot_force, log.row(ch_force_cmd_, k));
  store(in_.velocity_command, log.row(ch_v_cmd_, k));
  *log.row(ch_qp_, k) = out_.qp_iterations;
  for (int j = 0; j < kJoints; ++j) u[to_ctrl_[j]] = out_.tau[j];
  return status;
}

}  // namespace kiloloop::sil
