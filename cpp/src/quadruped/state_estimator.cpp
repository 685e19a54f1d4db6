#include "kiloloop/quadruped/state_estimator.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "kiloloop/quadruped/ldlt3.hpp"

namespace kiloloop {
namespace {
const Eigen::Vector3d kGravityWorld(0.0, 0.0, -9.81);
Status fail_attitude(std::string* why) {  // validate() passed: cannot happen, kept as a guard
  if (why) *why = "estimator: attitude filter refused its settings";
  return Status::kInvalidConfig;
}
}  // namespace

Status validate(const EstimatorConfig& c, std::string* why) {
  auto fail = [&](const char* msg) {
    if (why) *why = std::string("estimator: ") + msg;
    return Status::kInvalidConfig;
  };
  if (!(std::isfinite(c.dt) && c.dt > 0)) return fail("dt must be finite and > 0 [s]");
  if (!(c.attitude_gain >= 0 && c.attitude_gain <= 1))
    return fail("attitude_gain must be in [0, 1] (per-tick pull toward the IMU orientation)");
  if (!(std::isfinite(c.accel_noise) && c.accel_noise > 0) ||
      !(std::isfinite(c.leg_velocity_noise) && c.leg_velocity_noise > 0) ||
      !(std::isfinite(c.foothold_noise) && c.foothold_noise > 0))
    return fail("accel_noise [m/s^2], leg_velocity_noise [m/s], foothold_noise [m] must be finite and > 0");
  if (!(std::isfinite(c.velocity_gate) && c.velocity_gate >= 0))
    return fail("velocity_gate must be finite and >= 0 (0: off)");
  if (!(c.ground_filter >= 0 && c.ground_filter <= 1))
    return fail("ground_filter must be in [0, 1] (per touch-down weight)");
  const AttitudeFilterConfig& a = c.attitude;
  if (!(std::isfinite(a.gyro_noise_density) && a.gyro_noise_density > 0) ||
      !(std::isfinite(a.accel_noise_density) && a.accel_noise_density > 0) ||
      !(std::isfinite(a.accel_tolerance) && a.accel_tolerance > 0) ||
      !(std::isfinite(a.crossover) && a.crossover >= 0) ||
      !(std::isfinite(a.max_gyro_bias) && a.max_gyro_bias >= 0) ||
      !(std::isfinite(a.gyro_bias_random_walk) && a.gyro_bias_random_walk >= 0) ||
      !(std::isfinite(a.gyro_turn_on_bias) && a.gyro_turn_on_bias >= 0))
    return fail("attitude: gyro_noise_density, accel_noise_density, accel_tolerance must be finite "
                "and > 0; crossover (0: derived), max_gyro_bias, gyro_bias_random_walk [rad/s^2/sqrt(Hz)], "
                "gyro_turn_on_bias [rad/s] finite and >= 0");
  return Status::kOk;
}

Status StateEstimator::configure(const EstimatorConfig& config, std::string* why) {
  if (const Status s = validate(config, why); failed(s)) return s;
  cfg_ = config;
  initialised_ = false;
  if (!attitude_.configure(config.attitude, config.dt)) return fail_attitude(why);
  cfg_.attitude = attitude_.config();
  return Status::kOk;
}

Eigen::Quaterniond StateEstimator::initial_orientation(const Eigen::Vector3d& accel,
                                                       const Eigen::Quaterniond& q_imu) const noexcept {
  return cfg_.external_attitude ? q_imu.normalized() : AttitudeFilter::from_gravity(accel);
}

void StateEstimator::reset(const Eigen::Quaterniond& q0,
                           const std::array<LegMeasurement, kLegs>& legs, double foot_radius) {
  foot_radius_ = foot_radius;
  q_ = q0.normalized();
  attitude_.reset(q_);
  omega_.setZero();
  velocity_correction_.setZero();
  legs_corrected_ = false;
  const Eigen::Matrix3d R = q_.toRotationMatrix();
  // Put the trunk above the origin of x, y and let the lowest feet define the ground plane.
  double min_z = 0.0;
  for (int i = 0; i < kLegs; ++i) min_z = std::min(min_z, (R * legs[i].r).z());
  x_.setZero();
  x_[2] = -min_z + foot_radius;
  for (int i = 0; i < kLegs; ++i) footholds_[i] = x_.head<3>() + R * legs[i].r;
  foothold_latched_.fill(true);
  P_.reset(1e-4);
  normal_ = Eigen::Vector3d::UnitZ();
  initialised_ = false;  // the first fit takes the plane as it is, unfiltered
  fit_ground();
  initialised_ = true;
}

void StateEstimator::set_truth(const Eigen::Vector3d& p, const Eigen::Vector3d& v,
                               const Eigen::Quaterniond& q) noexcept {
  x_.head<3>() = p;
  x_.tail<3>() = v;
  q_ = q;
  attitude_.reset(q);
}

Status StateEstimator::update(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel,
                              const Eigen::Quaterniond& q_imu,
                              const std::array<LegMeasurement, kLegs>& legs) noexcept {
  const double dt = cfg_.dt;
  // Aided only after a tick whose legs corrected the velocity: without stance legs (the start's
  // drop, a hop) the raw specific force is taken, which the filter ignores in free fall (|f| ~ 0)
  // instead of counting the aided R^T (-g) as a perfect gravity reading for the start-up alignment.
  const bool aided = cfg_.velocity_aiding && !cfg_.external_attitude && legs_corrected_;
  update_orientation(gyro, accel, q_imu, aided);
  const Eigen::Matrix3d R = q_.toRotationMatrix();
  aligning_ = !cfg_.external_attitude && attitude_.aligning();

  // Predict with the accelerometer's specific force.
  const Eigen::Vector3d a = R * accel + kGravityWorld;
  x_.head<3>() += dt * x_.tail<3>() + 0.5 * dt * dt * a;
  x_.tail<3>() += dt * a;
  P_.predict(dt, cfg_.accel_noise);  // P = F P F^T + Q (axis_covariance.hpp)

  // Correct with the legs in contact (trust-weighted average: one 6-D measurement with H = I).
  // Each leg's weight is its trust, lowered for a leg whose velocity is inconsistent with the
  // prediction (EstimatorConfig::velocity_gate).
  const double leg_var = cfg_.leg_velocity_noise * cfg_.leg_velocity_noise;  // [m^2/s^2]
  Eigen::Matrix3d S_leg = Eigen::Matrix3d::Zero();
  S_leg.diagonal().setConstant(P_.velocity_variance() + leg_var);
  const Eigen::Matrix3d S_leg_inv = S_leg.inverse();
  int n = 0;
  double weight = 0.0;
  Eigen::Vector3d p_sum = Eigen::Vector3d::Zero(), v_sum = Eigen::Vector3d::Zero();
  for (int i = 0; i < kLegs; ++i) {
    const LegMeasurement& leg = legs[i];
    if (leg.touched_down || (aligning_ && leg.contact)) foothold_latched_[i] = false;
    if (!leg.contact) continue;
    const Eigen::Vector3d v_leg = -R * (leg.v_rel + omega_.cross(leg.r));  // [m/s] world
    double w = std::clamp(leg.trust, 0.0, 1.0);
    if (cfg_.velocity_gate > 0) {
      const Eigen::Vector3d e = v_leg - x_.tail<3>();
      const double d2 = e.dot(S_leg_inv * e);
      if (d2 > cfg_.velocity_gate) w *= cfg_.velocity_gate / d2;
    }
    if (!foothold_latched_[i]) {
      // Settling: the foothold follows the foot where the current estimate puts it.
      footholds_[i] = x_.head<3>() + R * leg.r;
      if (w >= 1.0) {
        foothold_latched_[i] = true;
        fit_ground();
      }
    }
    ++n;
    if (w <= 0.0) continue;
    p_sum += w * (footholds_[i] - R * leg.r);
    v_sum += w * v_leg;
    weight += w;
  }
  velocity_correction_.setZero();
  legs_corrected_ = false;
  if (n == 0) return Status::kEstimatorDegraded;
  if (weight < 1e-3) {  // only feet in transition: predict only, keep the ground as it is
    return Status::kOk;
  }
  Eigen::Matrix<double, 6, 1> z;
  z << p_sum / weight, v_sum / weight;
  // K = P (P + R)^-1, P = (I - K) P, R = diag(foothold_noise^2, leg_velocity_noise^2) / weight
  // per axis (axis_covariance.hpp: the 6x6 filter's numbers, per axis).
  const AxisGain K = P_.correct(cfg_.foothold_noise * cfg_.foothold_noise / weight,
                                cfg_.leg_velocity_noise * cfg_.leg_velocity_noise / weight);
  const Eigen::Matrix<double, 6, 1> e = z - x_;
  Eigen::Matrix<double, 6, 1> dx;
  for (int a = 0; a < 3; ++a) {
    dx[a] = K.pp * e[a] + K.pv * e[a + 3];
    dx[a + 3] = K.vp * e[a] + K.vv * e[a + 3];
  }
  x_ += dx;
  velocity_correction_ = dx.tail<3>() / dt;
  legs_corrected_ = true;

  // The plane's height follows the feet on the ground now. Leg odometry has no absolute height
  // reference, so the estimate (and the footholds latched from it) drift slowly in z (measured:
  // ~1 cm/s in a noisy trot); a plane filtered over many touch-downs then lags, and swing feet
  // aim centimetres into the ground. The slope (normal) still comes from the foothold fit.
  double offset = 0.0;
  for (int i = 0; i < kLegs; ++i) {
    if (!legs[i].contact) continue;
    const Eigen::Vector3d foot = x_.head<3>() + R * legs[i].r;
    offset += foot.z() - plane_[1] * foot.x() - plane_[2] * foot.y();
  }
  plane_[0] = offset / n - foot_radius_ / normal_.z();
  return Status::kOk;
}

Eigen::Vector3d StateEstimator::trunk_acceleration(const Eigen::Vector3d& accel) const noexcept {
  // The velocity filter's own acceleration over the last tick: the accelerometer's, rotated with
  // the current estimate, plus the legs' correction. Removed from the specific force this leaves
  // R^T (g - c): exact gravity when the estimate is right (c = 0), tilted by what the legs had to
  // correct otherwise.
  const Eigen::Quaterniond& q = attitude_.orientation();
  return q.conjugate() * (q * accel + kGravityWorld + velocity_correction_);
}

double StateEstimator::aiding_weight() const noexcept {
  // A tilt error d makes the legs correct (R_est - R) f, at most 2 sin(d / 2) |f| <= |f|: about
  // g in stance (the raw gate's band: |f| within (1 +- accel_tolerance) g). A correction beyond
  // g is no tilt error the filter can hold but feet that do not stand (measured: a shove tipping
  // the standing trunk, the lifted feet still counted as stance, |c| 10 -> 90 m/s^2 while the
  // trunk rolled from 6 to 20 deg; counted, they held the estimate 2.6 deg behind and the safe
  // stop 8 ticks late; Go1: 28, and 15 with this weight. The scenario's shove at 0.5 s lands in
  // the start-up alignment, where AttitudeFilter also gates the aided reading as the raw one: 0
  // late on both). Full weight up to g, none from (1 + accel_tolerance) g.
  const double g = -kGravityWorld.z();
  const double over = velocity_correction_.norm() / g - 1.0;
  return std::clamp(1.0 - over / cfg_.attitude.accel_tolerance, 0.0, 1.0);
}

void StateEstimator::update_orientation(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel,
                                        const Eigen::Quaterniond& q_imu,
                                        bool aided) noexcept {
  if (!cfg_.external_attitude) {
    if (aided) attitude_.update_aided(gyro, accel, trunk_acceleration(accel), aiding_weight());
    else attitude_.update(gyro, accel);
    q_ = attitude_.orientation();
    omega_ = attitude_.rate();
    return;
  }
  // External AHRS: integrate the gyro, then pull toward the AHRS's orientation output.
  omega_ = gyro;
  const Eigen::Vector3d half = 0.5 * cfg_.dt * gyro;
  const Eigen::Quaterniond dq(1.0, half.x(), half.y(), half.z());
  q_ = (q_ * dq).normalized();
  Eigen::Quaterniond target = q_imu;
  if (q_.dot(target) < 0.0) target.coeffs() = -target.coeffs();  // same hemisphere
  q_ = q_.slerp(cfg_.attitude_gain, target).normalized();
}

void StateEstimator::fit_ground() noexcept {
  // Least squares z = a + b x + c y through the four footholds (foot centres), then shifted down
  // by the foot radius along the normal to the ground surface.
  // The normal equations' sums over the feet for the row (1, x, y), each summed from zero foot by
  // foot as Eigen's `AtA += row * row.transpose(); Atz += row * z` did (its products by the 1 are
  // exact, so they are left out; AtA(0, 0) = 0 + 1 + 1 + 1 + 1 = 4 exactly): about a third of the
  // instructions of Eigen's outer products, which formed all nine entries of the symmetric AtA.
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, syy = 0.0, sz = 0.0, sxz = 0.0, syz = 0.0;
  for (const auto& f : footholds_) {
    sx += f.x();
    sy += f.y();
    sxx += f.x() * f.x();
    sxy += f.y() * f.x();
    syy += f.y() * f.y();
    sz += f.z();
    sxz += f.x() * f.z();
    syz += f.y() * f.z();
  }
  Eigen::Matrix3d AtA;
  AtA << 4.0, sx, sy, sx, sxx, sxy, sy, sxy, syy;
  const Eigen::Vector3d Atz(sz, sxz, syz);
  const Eigen::Vector3d sol = Ldlt3(AtA).solve(Atz);  // Eigen's ldlt() bit for bit (ldlt3.hpp)
  if (!sol.allFinite()) return;
  Eigen::Vector3d n(-sol[1], -sol[2], 1.0);
  n.normalize();
  const double w = initialised_ && !aligning_ ? cfg_.ground_filter : 1.0;
  normal_ = ((1.0 - w) * normal_ + w * n).normalized();
  plane_ = (1.0 - w) * plane_ + w * Eigen::Vector3d(sol[0] - foot_radius_ / n.z(), sol[1], sol[2]);
}

}  // namespace kiloloop
