#include "sil/press_adapter.hpp"

#include <algorithm>
#include <cmath>

namespace kiloloop::sil {

namespace {
// Rest-to-rest blend on s in [0, 1] (clamped): value, first and second derivative w.r.t. s.
// Powers through std::pow, as the Python reference it replaced (s**3 is C pow): same rounding.
void quintic_blend(double s, double* v, double* dv, double* ddv) noexcept {
  s = std::min(std::max(s, 0.0), 1.0);
  const double s2 = std::pow(s, 2.0), s3 = std::pow(s, 3.0), s4 = std::pow(s, 4.0), s5 = std::pow(s, 5.0);
  *v = 10 * s3 - 15 * s4 + 6 * s5;
  *dv = 30 * s2 - 60 * s3 + 30 * s4;
  *ddv = 60 * s - 180 * s2 + 120 * s3;
}
}  // namespace

void PressSlide::sample(double t, double* x, double* xd, double* xdd) const noexcept {
  double s, ds, dds;
  quintic_blend((t - settle) / slide_time, &s, &ds, &dds);
  *x = p0[0] + slide * s;
  *xd = slide * ds / slide_time;
  *xdd = slide * dds / std::pow(slide_time, 2.0);
}

Eigen::Vector3d site_force_to_world(const double* f_site, const double* quat) noexcept {
  // Unit quaternion to rotation matrix (world <- site); MuJoCo normalises framequat's output.
  const double w = quat[0], x = quat[1], y = quat[2], z = quat[3];
  Eigen::Matrix3d R;
  R << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
       2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
       2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
  return R * Eigen::Vector3d(f_site[0], f_site[1], f_site[2]);
}

PressAdapter::PressAdapter(CartesianTorqueController* controller, const PressSlide& slide,
                           const Eigen::Matrix3d& R0, double force)
    : c_(controller), nq_(controller->nq()), slide_(slide) {
  in_ = controller->make_input();
  out_ = controller->make_output();
  in_.R_ref = R0;
  in_.wrench_ref << 0.0, 0.0, -force, 0.0, 0.0, 0.0;
  in_.p_ref = slide.p0;
}

void PressAdapter::declare(LogBuffer& log) {
  // PressTick's channels, plus q.
  ch_x_ref_ = log.declare("x_ref", {});
  ch_force_ = log.declare("force", {3});
  ch_tau_ = log.declare("tau", {nq_});
  ch_status_ = log.declare("status", {});
  ch_q_ = log.declare("q", {nq_});
}

int PressAdapter::step(double t, double stamp, const double* y, double* u, LogBuffer& log, int k) noexcept {
  in_.t = t;
  in_.stamp = stamp;
  in_.q = Eigen::Map<const Eigen::VectorXd>(y, nq_);
  in_.qd = Eigen::Map<const Eigen::VectorXd>(y + nq_, nq_);
  double x, xd, xdd;
  slide_.sample(t, &x, &xd, &xdd);
  in_.p_ref = Eigen::Vector3d(x, slide_.p0[1], slide_.p0[2]);
  in_.twist_ref[0] = xd;
  in_.accel_ref[0] = xdd;
  // Sampled with q (same stamp): the force the tool applies, world frame.
  const Eigen::Vector3d f = site_force_to_world(y + 2 * nq_, y + 2 * nq_ + 3);
  in_.wrench_measured.head<3>() = f;
  const int status = static_cast<int>(c_->step(in_, out_));
  *log.row(ch_x_ref_, k) = x;
  std::copy(f.data(), f.data() + 3, log.row(ch_force_, k));
  std::copy(out_.tau.data(), out_.tau.data() + nq_, log.row(ch_tau_, k));
  *log.row(ch_status_, k) = status;
  std::copy(in_.q.data(), in_.q.data() + nq_, log.row(ch_q_, k));
  std::copy(out_.tau.data(), out_.tau.data() + nq_, u);
  return status;
}

}  // namespace kiloloop::sil
