// StateEstimator's velocity aiding: the velocity filter's own trunk acceleration (accelerometer
// plus the legs' correction) is removed from the accelerometer before the attitude filter takes it
// as gravity.
#include "kiloloop/quadruped/state_estimator.hpp"
#include "kiloloop/model/gravity.hpp"
#include "attitude_angles.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace kiloloop {
namespace {

// A level trunk trotting round a bend: 0.5 m/s forward (body x) turning at 0.5 rad/s, four feet
// on the ground. In the body frame v_b is constant and the trunk's acceleration is the centripetal
// w x v_b = 0.25 m/s^2 to the left; the accelerometer reads it on top of gravity. Without aiding
// the filter takes "up" to lean into the bend by atan(0.25 / g) = 1.46 deg (a steady roll error);
// with it (after the 0.7 s start-up alignment, which leans too) the legs correct nothing once the
// estimate is level, and it returns there: 20 s are 28 time constants 1 / k_p.
double roll_error_in_a_turn(bool aiding) {
  EstimatorConfig config;
  config.velocity_aiding = aiding;
  StateEstimator estimator;
  std::string why;
  EXPECT_EQ(estimator.configure(config, &why), Status::kOk) << why;
  const Eigen::Vector3d w(0.0, 0.0, 0.5), v(0.5, 0.0, 0.0);  // [rad/s], [m/s] body frame
  const Eigen::Vector3d f = w.cross(v) + Eigen::Vector3d(0.0, 0.0, kGravity);
  std::array<LegMeasurement, StateEstimator::kLegs> legs;
  const double x[4] = {0.2, 0.2, -0.2, -0.2}, y[4] = {0.1, -0.1, 0.1, -0.1};
  for (int i = 0; i < StateEstimator::kLegs; ++i) {
    legs[i].contact = true;
    legs[i].r = Eigen::Vector3d(x[i], y[i], -0.3);
    legs[i].v_rel = -(v + w.cross(legs[i].r));  // the foot stands still in the world
    // The trunk travels over feet that stay put: a stepping robot relatches its footholds, here
    // every tick (else the first footholds would pull the position back and that correction
    // would leak into the velocity's).
    legs[i].touched_down = true;
  }
  estimator.reset(Eigen::Quaterniond::Identity(), legs, 0.02);
  for (int k = 0; k < 20000; ++k) estimator.update(w, f, Eigen::Quaterniond::Identity(), legs);
  return roll_of(estimator.orientation());
}

TEST(StateEstimator, VelocityAidingRemovesTheCentripetalAccelerationOfATurn) {
  EXPECT_GT(std::abs(roll_error_in_a_turn(false)), 1.0 * M_PI / 180.0);
  EXPECT_LT(std::abs(roll_error_in_a_turn(true)), 0.01 * M_PI / 180.0);
}

// An estimator configured with `config`, reset on four feet standing still under the trunk
// (0.3 m below it, 0.4 x 0.2 m apart); `legs` gets those feet.
StateEstimator standing_estimator(const EstimatorConfig& config,
                                  std::array<LegMeasurement, StateEstimator::kLegs>* legs) {
  StateEstimator estimator;
  std::string why;
  EXPECT_EQ(estimator.configure(config, &why), Status::kOk) << why;
  const double x[4] = {0.2, 0.2, -0.2, -0.2}, y[4] = {0.1, -0.1, 0.1, -0.1};
  for (int i = 0; i < StateEstimator::kLegs; ++i) {
    (*legs)[i].contact = true;
    (*legs)[i].r = Eigen::Vector3d(x[i], y[i], -0.3);
    (*legs)[i].v_rel = Eigen::Vector3d::Zero();
  }
  estimator.reset(Eigen::Quaterniond::Identity(), *legs, 0.02);
  return estimator;
}

// A standing trunk on four feet, one of which the leg kinematics says moves down at 4 m/s (a
// foot counted as in contact that is in fact driven through the air): it implies the trunk rises
// at 4 m/s. Counted in full it drags the estimate toward the mean of the legs (1 m/s); gated
// (velocity_gate) its weight falls with the square of its distance and the estimate stays put.
double vertical_velocity_with_one_flying_leg(double gate) {
  EstimatorConfig config;
  config.velocity_gate = gate;
  std::array<LegMeasurement, StateEstimator::kLegs> legs;
  StateEstimator estimator = standing_estimator(config, &legs);
  legs[0].v_rel = Eigen::Vector3d(0.0, 0.0, -4.0);  // [m/s] the flying foot, trunk frame
  const Eigen::Vector3d gyro = Eigen::Vector3d::Zero(), f(0.0, 0.0, kGravity);
  for (int k = 0; k < 50; ++k) estimator.update(gyro, f, Eigen::Quaterniond::Identity(), legs);
  return estimator.velocity().z();
}

TEST(StateEstimator, VelocityGateKeepsAFootMovingThroughTheAirOutOfTheEstimate) {
  EXPECT_GT(vertical_velocity_with_one_flying_leg(0.0), 0.5);
  EXPECT_LT(std::abs(vertical_velocity_with_one_flying_leg(EstimatorConfig().velocity_gate)), 0.02);
}

// The gate must not lock the filter out of a velocity every leg agrees on (a change the
// accelerometer did not report): each leg's weight falls alike, the mean stays the legs' velocity,
// and as the estimate approaches it the weights return to the trust. All four feet say the trunk
// moves forward at 0.5 m/s from rest: within 1 s the estimate is there to 1 cm/s.
TEST(StateEstimator, VelocityGateStillFollowsAVelocityAllLegsAgreeOn) {
  std::array<LegMeasurement, StateEstimator::kLegs> legs;
  StateEstimator estimator = standing_estimator(EstimatorConfig(), &legs);
  const Eigen::Vector3d gyro = Eigen::Vector3d::Zero(), f(0.0, 0.0, kGravity);
  for (int i = 0; i < StateEstimator::kLegs; ++i) {
    legs[i].v_rel = Eigen::Vector3d(-0.5, 0.0, 0.0);  // [m/s] feet still, trunk moving forward
    legs[i].touched_down = true;  // footholds relatched every tick: the trunk travels over them
  }
  for (int k = 0; k < 1000; ++k) estimator.update(gyro, f, Eigen::Quaterniond::Identity(), legs);
  EXPECT_NEAR(estimator.velocity().x(), 0.5, 0.01);
}

}  // namespace
}  // namespace kiloloop
