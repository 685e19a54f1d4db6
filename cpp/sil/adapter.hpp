#pragma once
// The adapter interface of the native SIL loop: one per (robot family, controller). The loop owns
// the plant side (MuJoCo, sensor/actuator models, delays, events, ground-truth probes); an adapter
// maps one delayed measurement vector onto its compiled controller's Input, steps it and writes
// the actuator command. Glue only: no control logic, no robot constants.
//   arm: y = [q (nq); qd (nq)], u = tau (nq)
//   a quadruped or aerial adapter declares its own layout (joint + IMU signals, rotor thrusts).
#include <string>

#include "sil/events.hpp"
#include "sil/io_record.hpp"
#include "sil/log_buffer.hpp"

namespace kiloloop::sil {

class Adapter {
 public:
  virtual ~Adapter() = default;
  virtual int measurement_size() const = 0;  // length of y
  virtual int command_size() const = 0;      // length of u
  // Configure time: the channels this adapter logs every tick.
  virtual void declare(LogBuffer& log) = 0;
  // Before a run: controller and adapter state back to their configured values where the
  // controller allows it (kiloloop controllers are built fresh per run by the Python side).
  virtual void reset() noexcept {}
  // A scheduled event addressed to the controller side (e-stop, reference change).
  virtual void on_event(const Event& event) noexcept { (void)event; }
  // One control tick at time t [s] on a measurement sampled at stamp [s]; writes u and the log
  // row k; returns the step's Status as an int.
  virtual int step(double t, double stamp, const double* y, double* u, LogBuffer& log, int k) noexcept = 0;
  // The back-to-back log (kiloloop/firmware/record.hpp): bytes of the stepped controller's input
  // and output records ({0, 0}: its controller has no firmware family), and the records of the
  // tick just stepped, input then output, into out (sizes: what io_record_bytes returned, kept
  // by the caller; sizes.total() bytes). Configure time and after step respectively;
  // allocation-free.
  virtual IoRecordBytes io_record_bytes() const { return {}; }
  virtual void write_io_record(const IoRecordBytes& sizes, unsigned char* out) const noexcept {
    (void)sizes;
    (void)out;
  }
};

}  // namespace kiloloop::sil
