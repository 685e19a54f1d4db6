// The two attitude laws: textbook terms, agreement for small errors, the hysteretic shortest
// path near 180 deg, closed-loop convergence on a rigid body, anti-windup, allocation-free.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"
#include "kiloloop/aerial/attitude_controller.hpp"

namespace kiloloop {
namespace {

const Eigen::Matrix3d kJ = Eigen::Vector3d(0.015, 0.015, 0.027).asDiagonal();

AttitudeController make(AttitudeLawType law, Eigen::Vector3d ki = Eigen::Vector3d::Zero()) {
  AttitudeControlConfig c;
  c.law = law;
  c.gains.ki = ki;
  AttitudeController a;
  std::string why;
  EXPECT_EQ(AttitudeController::configure(c, kJ, &a, &why), Status::kOk) << why;
  return a;
}

Eigen::Quaterniond axis_angle(double angle, const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

TEST(AttitudeLaws, GyroscopicTermAtZeroError) {
  for (auto law : {AttitudeLawType::kQuaternionPd, AttitudeLawType::kGeometricSo3}) {
    AttitudeControlConfig c;
    c.law = law;
    c.gains.kd.setZero();
    AttitudeController a;
    ASSERT_EQ(AttitudeController::configure(c, kJ, &a, nullptr), Status::kOk);
    const Eigen::Vector3d w(1.0, -2.0, 3.0);
    Eigen::Vector3d tau;
    AttitudeTarget target;
    target.q = Eigen::Quaterniond::Identity();
    // Lee's law with omega_des = 0 has no hat(W) term; both reduce to W x J W.
    a.step(Eigen::Quaterniond::Identity(), w, target, false, &tau);
    EXPECT_LT((tau - w.cross(kJ * w)).norm(), 1e-14);
  }
}

TEST(AttitudeLaws, AgreeForSmallErrorsAndPushBack) {
  AttitudeController quat = make(AttitudeLawType::kQuaternionPd);
  AttitudeController lee = make(AttitudeLawType::kGeometricSo3);
  const Eigen::Quaterniond q = axis_angle(0.01, Eigen::Vector3d(1, 2, 3));
  AttitudeTarget target;
  Eigen::Vector3d t1, t2;
  quat.step(q, Eigen::Vector3d::Zero(), target, false, &t1);
  lee.step(q, Eigen::Vector3d::Zero(), target, false, &t2);
  EXPECT_LT((t1 - t2).norm(), 1e-4 * t1.norm());
  // Restoring: torque opposes the rotation vector.
  EXPECT_LT(t1.dot(Eigen::Vector3d(1, 2, 3)), 0.0);
  // e_R is the rotation vector to first order.
  EXPECT_LT((quat.error() - 0.01 * Eigen::Vector3d(1, 2, 3).normalized()).norm(), 1e-6);
}

TEST(AttitudeLaws, QuaternionLawDoesNotChatterAt180Degrees) {
  AttitudeController quat = make(AttitudeLawType::kQuaternionPd);
  AttitudeTarget target;
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.02);
  // The error angle dithers around 180 deg (w of q_err around 0): the plain sign(w) rule would
  // flip the torque on every sample; the hysteretic rule keeps one direction.
  int flips = 0;
  double prev = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const Eigen::Quaterniond q = axis_angle(M_PI + noise(rng), Eigen::Vector3d::UnitX());
    Eigen::Vector3d tau;
    quat.step(q, Eigen::Vector3d::Zero(), target, false, &tau);
    if (k > 0 && tau.x() * prev < 0) ++flips;
    prev = tau.x();
    EXPECT_GT(std::abs(tau.x()), 1.0);  // full push, never a stall at the flip
  }
  EXPECT_EQ(flips, 0);
}

// Integrates a free rigid body under each law from a 60 deg error with a spin.
double settle_error(AttitudeLawType law) {
  AttitudeController a = make(law);
  Eigen::Quaterniond q = axis_angle(1.0, Eigen::Vector3d(1, -1, 0.5));
  Eigen::Vector3d w(0.5, -0.3, 0.8);
  AttitudeTarget target;
  target.q = axis_angle(0.3, Eigen::Vector3d::UnitZ());
  const double dt = 0.001;
  for (int k = 0; k < 3000; ++k) {
    Eigen::Vector3d tau;
    a.step(q, w, target, false, &tau);
    const Eigen::Vector3d wdot = kJ.inverse() * (tau - w.cross(kJ * w));
    w += dt * wdot;
    const Eigen::Quaterniond dq(Eigen::AngleAxisd(w.norm() * dt, w.normalized()));
    q = (q * dq).normalized();
  }
  return q.angularDistance(target.q);
}

TEST(AttitudeLaws, BothConvergeOnARigidBody) {
  EXPECT_LT(settle_error(AttitudeLawType::kQuaternionPd), 1e-4);
  EXPECT_LT(settle_error(AttitudeLawType::kGeometricSo3), 1e-4);
}

TEST(AttitudeController, IntegralIsClampedAndFrozenWhenSaturated) {
  AttitudeController a = make(AttitudeLawType::kQuaternionPd, Eigen::Vector3d(100, 100, 100));
  const Eigen::Quaterniond q = axis_angle(0.2, Eigen::Vector3d::UnitX());
  AttitudeTarget target;
  Eigen::Vector3d tau;
  for (int k = 0; k < 100; ++k) a.step(q, Eigen::Vector3d::Zero(), target, true, &tau);
  EXPECT_EQ(a.integral().norm(), 0.0);  // frozen
  for (int k = 0; k < 100000; ++k) a.step(q, Eigen::Vector3d::Zero(), target, false, &tau);
  // ki * integral never exceeds the limit (30 rad/s^2 on x).
  EXPECT_NEAR(100.0 * a.integral().x(), 30.0, 1e-9);
}

TEST(AttitudeController, BadInputs) {
  AttitudeController a = make(AttitudeLawType::kGeometricSo3);
  AttitudeTarget target;
  Eigen::Vector3d tau;
  EXPECT_EQ(a.step(Eigen::Quaterniond::Identity(), Eigen::Vector3d(std::nan(""), 0, 0), target,
                   false, &tau),
            Status::kNonFiniteMeasurement);
  EXPECT_TRUE(tau.allFinite());
  target.omega.x() = INFINITY;
  EXPECT_EQ(a.step(Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), target, false, &tau),
            Status::kNonFiniteReference);
  AttitudeControlConfig c;
  c.gains.kp.x() = 0.0;
  AttitudeController b;
  std::string why;
  EXPECT_EQ(AttitudeController::configure(c, kJ, &b, &why), Status::kInvalidConfig);
  EXPECT_NE(why.find("kp"), std::string::npos);
}

TEST(AttitudeController, IsAllocationFree) {
  AttitudeController a = make(AttitudeLawType::kQuaternionPd, Eigen::Vector3d(10, 10, 10));
  AttitudeController b = make(AttitudeLawType::kGeometricSo3);
  AttitudeTarget target;
  Eigen::Vector3d tau;
  testing::AllocationScope scope;
  for (int k = 0; k < 10000; ++k) {
    const Eigen::Quaterniond q = axis_angle(1e-4 * k, Eigen::Vector3d(1, 1, 0));
    a.step(q, Eigen::Vector3d(0.1, 0.2, 0.3), target, k % 7 == 0, &tau);
    b.step(q, Eigen::Vector3d(0.1, 0.2, 0.3), target, false, &tau);
  }
  EXPECT_EQ(scope.count(), 0u);
}

}  // namespace
}  // namespace kiloloop
