#pragma once
// Native SIL adapter of the aerial family (python/kiloloop/sil/aerial_family.py builds it): maps
// the measurement and the reference table onto the AerialController and its output onto the
// rotors and arm motors, logging the controller's channels.
//   y = [position (3); velocity (3); gyro (3); accel (3); quat (4); q (nq); qd (nq)]
//       body origin position [m] and linear velocity [m/s] (world: the motion-capture stand-in,
//       the free joint's qpos / qvel), the IMU site's sensors, the arm encoders in plant order
//   u = [thrust (n rotors) [N]; tau (nq) [N m] plant order]
// References are data: a table sampled on the tick grid (row k for tick k; the last row after
// its end), one row = kReferenceWidth + 3 nq values in the order of the Ref enum below
// (sil/aerial_signals.py reference_table samples a scenario's command into it).
#include <vector>

#include "kiloloop/aerial/aerial_controller.hpp"
#include "sil/adapter.hpp"

namespace kiloloop::sil {

class AerialAdapter final : public Adapter {
 public:
  // Offsets in a reference row; q_ref, qd_ref, qdd_ref (nq each) follow at kReferenceWidth.
  enum Ref : int { kPosition = 0, kVelocity = 3, kAcceleration = 6, kYaw = 9, kFlightMode = 10,
                   kQuat = 11, kArmMode = 15, kEePosition = 16, kEeVelocity = 19, kReferenceWidth = 22 };
  static constexpr int kBodySignals = 16;  // y entries before the arm's
  // controller: borrowed (the binding keeps its Python object alive). to_ctrl[j]: plant index of
  // controller joint j. references: (rows x width) row-major, rows >= 1 (checked by the binding).
  AerialAdapter(AerialController* controller, std::vector<int> to_ctrl, std::vector<double> references);
  int measurement_size() const override { return kBodySignals + 2 * nq_; }
  int command_size() const override { return n_ + nq_; }
  void declare(LogBuffer& log) override;
  int step(double t, double stamp, const double* y, double* u, LogBuffer& log, int k) noexcept override;
  IoRecordBytes io_record_bytes() const override { return sil::io_record_bytes(in_, out_); }
  void write_io_record(const IoRecordBytes& sizes, unsigned char* p) const noexcept override {
    sil::write_io_record(in_, out_, sizes, p);
  }
  static int width(int nq) { return kReferenceWidth + 3 * nq; }

 private:
  void load_references(int k) noexcept;

  AerialController* c_;
  int nq_, n_;
  std::vector<int> to_ctrl_;
  std::vector<double> ref_;  // (rows x width)
  int rows_ = 0;
  AerialInput in_;
  AerialOutput out_;
  int ch_status_ = 0, ch_pos_ref_ = 0, ch_quat_des_ = 0, ch_tilt_ = 0, ch_safe_stop_ = 0, ch_thrust_cmd_ = 0,
      ch_saturated_ = 0, ch_tau_ = 0, ch_reaction_ = 0, ch_q_ref_ = 0;
};

}  // namespace kiloloop::sil
