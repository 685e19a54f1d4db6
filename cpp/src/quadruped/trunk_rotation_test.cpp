// trunk_acceleration: the floating base's forward dynamics the Smith predictor turns the trunk
// with (trunk_rotation.hpp), on our model standing.
#include "kiloloop/quadruped/trunk_rotation.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "kiloloop/model/gravity.hpp"
#include "kiloloop/quadruped/quadruped_controller.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {

struct Standing {
  QuadrupedController c;
  FreeLegInertia inertia;
  LegTorques legs;
};

Standing standing() {
  const RobotModelPtr model = testing::load_quadruped();
  std::string why;
  Standing s;
  QuadrupedConfig config;
  config.foot_radius = 0.02;
  EXPECT_EQ(QuadrupedController::configure(config, model, &s.c, &why), Status::kOk) << why;
  s.inertia = free_leg_inertia(*model, config.trunk_link, config.feet, s.c.stand_pose(), s.c.mass(),
                               s.c.com(), s.c.inertia());
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d q = s.c.stand_pose().segment<3>(3 * i);
    s.legs.jacobian[i] = s.c.leg(i).jacobian(q);
    s.legs.foot[i] = s.c.leg(i).foot_position(q) - s.c.com();
  }
  return s;
}

// Four feet pinned, each pushing with a force that together carries the weight with no moment
// about the CoM, the legs' torques -J^T f (gravity compensation aside): the trunk stays at rest.
TEST(TrunkRotation, RestsWhenTheFeetCarryTheWeight) {
  Standing s = standing();
  const double weight = s.c.mass() * kGravity;
  Eigen::Matrix<double, 3, 4> E;  // sum fz = weight; sum x fz = 0; sum y fz = 0
  for (int i = 0; i < 4; ++i) E.col(i) << 1.0, s.legs.foot[i].x(), s.legs.foot[i].y();
  const Eigen::Vector4d fz = E.completeOrthogonalDecomposition().solve(Eigen::Vector3d(weight, 0, 0));
  for (int i = 0; i < 4; ++i) {
    s.legs.pinned[i] = true;
    s.legs.torque[i] = -s.legs.jacobian[i].transpose() * Eigen::Vector3d(0, 0, fz[i]);
  }
  Eigen::Matrix<double, 6, 1> a = Eigen::Matrix<double, 6, 1>::Constant(1.0);
  ASSERT_TRUE(trunk_acceleration(s.inertia, s.legs, Eigen::Vector3d(0, 0, -kGravity), &a));
  EXPECT_LT(a.head<3>().norm(), 1e-9);  // [m/s^2]
  EXPECT_LT(a.tail<3>().norm(), 1e-9);  // [rad/s^2]
}

// All legs free in the air, one abduction motor pushing: the robot's angular momentum about its
// CoM does not change (no external moment), so the trunk turns against the leg:
// C nu_dot + sum A q_dd = [m g; 0] with q_dd = H^-1 (u - A^T nu_dot).
TEST(TrunkRotation, AFreeLegsTorqueTurnsTheTrunkWithMomentumConserved) {
  Standing s = standing();
  s.legs.torque[0] = Eigen::Vector3d(1.0, 0.0, 0.0);  // [N m] FL abduction
  Eigen::Matrix<double, 6, 1> a;
  const Eigen::Vector3d g(0, 0, -kGravity);
  ASSERT_TRUE(trunk_acceleration(s.inertia, s.legs, g, &a));
  Eigen::Matrix<double, 6, 1> rate = s.inertia.composite * a;
  for (int i = 0; i < 4; ++i)
    rate += s.inertia.momentum[i] *
            (s.inertia.joint_inertia_inverse[i] * (s.legs.torque[i] - s.inertia.momentum[i].transpose() * a));
  EXPECT_NEAR(rate[0], 0.0, 1e-9);
  EXPECT_NEAR(rate[1], 0.0, 1e-9);
  EXPECT_NEAR(rate[2], s.c.mass() * g.z(), 1e-9);
  EXPECT_LT(rate.tail<3>().norm(), 1e-9);
  EXPECT_GT(std::abs(a[3]), 1.0);  // [rad/s^2] the trunk rolls: 1 N m on ~0.1 kg m^2
}

}  // namespace
}  // namespace kiloloop
