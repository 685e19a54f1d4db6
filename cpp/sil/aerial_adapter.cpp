#include "sil/aerial_adapter.hpp"

#include <algorithm>

namespace kiloloop::sil {

namespace {
template <class V>
void store(const V& v, double* row) noexcept { std::copy(v.data(), v.data() + v.size(), row); }
}  // namespace

AerialAdapter::AerialAdapter(AerialController* controller, std::vector<int> to_ctrl, std::vector<double> references)
    : c_(controller), nq_(controller->nq()), n_(controller->n_rotors()), to_ctrl_(std::move(to_ctrl)),
      ref_(std::move(references)) {
  rows_ = static_cast<int>(ref_.size() / width(nq_));
  in_ = c_->make_input();
  out_ = c_->make_output();
}

void AerialAdapter::declare(LogBuffer& log) {
  // The channels (and shapes) AerialRig._record writes from the controller's side.
  ch_status_ = log.declare("status", {});
  ch_pos_ref_ = log.declare("pos_ref", {3});
  ch_quat_des_ = log.declare("quat_des", {4});
  ch_tilt_ = log.declare("tilt", {});
  ch_safe_stop_ = log.declare("safe_stop", {});
  ch_thrust_cmd_ = log.declare("thrust_cmd", {n_});
  ch_saturated_ = log.declare("rotors_saturated", {});
  ch_tau_ = log.declare("tau", {nq_});
  ch_reaction_ = log.declare("reaction", {6});
  ch_q_ref_ = log.declare("q_ref", {nq_});
}

void AerialAdapter::load_references(int k) noexcept {
  const double* r = ref_.data() + static_cast<size_t>(std::min(k, rows_ - 1)) * width(nq_);
  in_.position_ref = Eigen::Vector3d(r[kPosition], r[kPosition + 1], r[kPosition + 2]);
  in_.velocity_ref = Eigen::Vector3d(r[kVelocity], r[kVelocity + 1], r[kVelocity + 2]);
  in_.acceleration_ref = Eigen::Vector3d(r[kAcceleration], r[kAcceleration + 1], r[kAcceleration + 2]);
  in_.yaw_ref = r[kYaw];
  in_.flight_mode = r[kFlightMode] != 0.0 ? FlightMode::kAttitude : FlightMode::kPosition;
  in_.quat_ref = Eigen::Vector4d(r[kQuat], r[kQuat + 1], r[kQuat + 2], r[kQuat + 3]);
  in_.arm_mode = r[kArmMode] != 0.0 ? ArmMode::kEndEffector : ArmMode::kJoints;
  in_.ee_position_ref = Eigen::Vector3d(r[kEePosition], r[kEePosition + 1], r[kEePosition + 2]);
  in_.ee_velocity_ref = Eigen::Vector3d(r[kEeVelocity], r[kEeVelocity + 1], r[kEeVelocity + 2]);
  const double* arm = r + kReferenceWidth;
  for (int j = 0; j < nq_; ++j) {
    in_.q_ref[j] = arm[j];
    in_.qd_ref[j] = arm[nq_ + j];
    in_.qdd_ref[j] = arm[2 * nq_ + j];
  }
}

int AerialAdapter::step(double t, double stamp, const double* y, double* u, LogBuffer& log, int k) noexcept {
  in_.t = t;
  in_.stamp = stamp;
  in_.position = Eigen::Vector3d(y[0], y[1], y[2]);
  in_.velocity = Eigen::Vector3d(y[3], y[4], y[5]);
  in_.gyro = Eigen::Vector3d(y[6], y[7], y[8]);
  in_.accel = Eigen::Vector3d(y[9], y[10], y[11]);
  in_.quat = Eigen::Vector4d(y[12], y[13], y[14], y[15]);
  for (int j = 0; j < nq_; ++j) {
    in_.q[j] = y[kBodySignals + to_ctrl_[j]];
    in_.qd[j] = y[kBodySignals + nq_ + to_ctrl_[j]];
  }
  load_references(k);
  const int status = static_cast<int>(c_->step(in_, out_));
  *log.row(ch_status_, k) = status;
  store(in_.position_ref, log.row(ch_pos_ref_, k));
  store(out_.quat_des, log.row(ch_quat_des_, k));
  *log.row(ch_tilt_, k) = out_.tilt;
  *log.row(ch_safe_stop_, k) = out_.safe_stop ? 1.0 : 0.0;
  store(out_.thrust, log.row(ch_thrust_cmd_, k));
  *log.row(ch_saturated_, k) = out_.rotors_saturated ? 1.0 : 0.0;
  store(out_.tau, log.row(ch_tau_, k));
  store(out_.reaction, log.row(ch_reaction_, k));
  store(out_.q_ref, log.row(ch_q_ref_, k));
  for (int i = 0; i < n_; ++i) u[i] = out_.thrust[i];
  for (int j = 0; j < nq_; ++j) u[n_ + to_ctrl_[j]] = out_.tau[j];
  return status;
}

}  // namespace kiloloop::sil
