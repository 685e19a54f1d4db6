#include "kiloloop/kinematics/leg_kinematics.hpp"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/jntarray.hpp>

#include "alloc_counter.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {

const char* kFeet[4] = {"FL_foot", "FR_foot", "RL_foot", "RR_foot"};

// The closed form agrees with KDL's chain FK from the same URDF, and the Jacobian with its
// finite difference, on random configurations of every leg.
TEST(LegKinematics, MatchesKdlAndFiniteDifferences) {
  const RobotModel model = *testing::load_quadruped();
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const char* foot : kFeet) {
    LegGeometry g;
    std::string why;
    ASSERT_EQ(leg_geometry_from_model(model, "trunk", foot, &g, &why), Status::kOk) << why;
    const LegKinematics leg(g);
    KDL::Chain chain;
    ASSERT_TRUE(model.tree().getChain("trunk", foot, chain));
    KDL::ChainFkSolverPos_recursive fk(chain);
    KDL::JntArray qk(3);
    for (int k = 0; k < 100; ++k) {
      const Eigen::Vector3d q(0.5 * u(rng), 0.9 + u(rng), -1.6 + 0.8 * u(rng));
      for (int j = 0; j < 3; ++j) qk(j) = q[j];
      KDL::Frame T;
      fk.JntToCart(qk, T);
      const Eigen::Vector3d p = leg.foot_position(q);
      EXPECT_LT((p - Eigen::Vector3d(T.p.x(), T.p.y(), T.p.z())).norm(), 1e-12) << foot;
      const Eigen::Matrix3d J = leg.jacobian(q);
      for (int j = 0; j < 3; ++j) {
        Eigen::Vector3d qh = q;
        qh[j] += 1e-7;
        EXPECT_LT(((leg.foot_position(qh) - p) / 1e-7 - J.col(j)).norm(), 1e-5) << foot;
      }
    }
  }
}

// foot_and_jacobian (one set of sines and cosines) is the two separate calls bit for bit, on
// every leg of the model (mirrored signs included) and over the joints' whole circle.
TEST(LegKinematics, FootAndJacobianEqualsTheSeparateCallsExactly) {
  const RobotModel model = *testing::load_quadruped();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3.2, 3.2);
  for (const char* foot : kFeet) {
    LegGeometry g;
    std::string why;
    ASSERT_EQ(leg_geometry_from_model(model, "trunk", foot, &g, &why), Status::kOk) << why;
    const LegKinematics leg(g);
    for (int k = 0; k < 1000; ++k) {
      const Eigen::Vector3d q(u(rng), u(rng), u(rng));
      Eigen::Vector3d p;
      Eigen::Matrix3d J;
      leg.foot_and_jacobian(q, &p, &J);
      const Eigen::Vector3d p_ref = leg.foot_position(q);
      const Eigen::Matrix3d J_ref = leg.jacobian(q);
      for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(p[i], p_ref[i]) << foot;
        for (int j = 0; j < 3; ++j) EXPECT_EQ(J(i, j), J_ref(i, j)) << foot;
      }
    }
  }
}

TEST(LegKinematics, InverseRoundTripsAndReportsUnreachable) {
  const RobotModel model = *testing::load_quadruped();
  LegGeometry g;
  std::string why;
  ASSERT_EQ(leg_geometry_from_model(model, "trunk", "RR_foot", &g, &why), Status::kOk) << why;
  const LegKinematics leg(g);
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 500; ++k) {
    const Eigen::Vector3d q(0.6 * u(rng), 0.9 + 0.8 * u(rng), -1.6 + 0.9 * u(rng));
    Eigen::Vector3d sol(9, 9, 9);
    ASSERT_EQ(leg.inverse(leg.foot_position(q), sol), Status::kOk) << q.transpose();
    EXPECT_LT((sol - q).norm(), 1e-9) << q.transpose();
  }
  Eigen::Vector3d keep(0.1, 0.2, -0.3);
  EXPECT_EQ(leg.inverse(g.abd_origin + Eigen::Vector3d(0, 0, -2.0), keep), Status::kUnreachable);
  EXPECT_EQ(keep, Eigen::Vector3d(0.1, 0.2, -0.3));  // untouched on failure
  testing::AllocationScope scope;
  Eigen::Vector3d q(0, 0.9, -1.8);
  for (int k = 0; k < 10000; ++k) leg.inverse(leg.foot_position(q), q);
  EXPECT_EQ(scope.count(), 0u);
}

// One leg of an unusual layout: the pitch joint below and behind the abduction axis, the knee
// offset along the hip pitch axis and in x, the foot off the shank line, the knee axis along -y
// and bending forward. FK and Jacobian match KDL; IK round-trips with the forward knee.
const char* kOddLeg = R"(<robot name="odd">
  <link name="trunk"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="abd" type="revolute"><parent link="trunk"/><child link="hip"/><origin xyz="0.2 0.05 0.01"/>
    <axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="5" velocity="10"/></joint>
  <link name="hip"><inertial><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="pitch" type="revolute"><parent link="hip"/><child link="thigh"/><origin xyz="-0.01 0.03 -0.02"/>
    <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="5" velocity="10"/></joint>
  <link name="thigh"><inertial><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="knee" type="revolute"><parent link="thigh"/><child link="shank"/><origin xyz="0.01 0.02 -0.15"/>
    <axis xyz="0 -1 0"/><limit lower="-2.6" upper="-0.1" effort="5" velocity="10"/></joint>
  <link name="shank"><inertial><mass value="0.05"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="foot_fixed" type="fixed"><parent link="shank"/><child link="foot"/><origin xyz="-0.005 0.01 -0.16"/></joint>
  <link name="foot"/>
</robot>)";

TEST(LegKinematics, AnyAbductionPitchKneeLayout) {
  RobotModel model;
  std::string why;
  ASSERT_EQ(model_from_urdf_string(kOddLeg, "", "", &model, &why), Status::kOk) << why;
  LegGeometry g;
  ASSERT_EQ(leg_geometry_from_model(model, "trunk", "foot", &g, &why), Status::kOk) << why;
  EXPECT_NEAR(g.l_abd, 0.06, 1e-12);  // hip, knee and foot offsets along the pitch axis
  EXPECT_EQ(g.sign[2], -1.0);
  EXPECT_EQ(g.knee, KneeDirection::kForward);  // -y axis with negative limits: bends forward
  const LegKinematics leg(g);
  KDL::Chain chain;
  ASSERT_TRUE(model.tree().getChain("trunk", "foot", chain));
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::JntArray qk(3);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int round_trips = 0;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d q(0.5 * u(rng), 0.6 * u(rng), -1.3 + 1.1 * u(rng));
    for (int j = 0; j < 3; ++j) qk(j) = q[j];
    KDL::Frame T;
    fk.JntToCart(qk, T);
    const Eigen::Vector3d p = leg.foot_position(q);
    ASSERT_LT((p - Eigen::Vector3d(T.p.x(), T.p.y(), T.p.z())).norm(), 1e-12);
    const Eigen::Matrix3d J = leg.jacobian(q);
    for (int j = 0; j < 3; ++j) {
      Eigen::Vector3d qh = q;
      qh[j] += 1e-7;
      EXPECT_LT(((leg.foot_position(qh) - p) / 1e-7 - J.col(j)).norm(), 1e-5);
    }
    Eigen::Vector3d sol = Eigen::Vector3d::Zero();
    if (leg.inverse(p, sol) == Status::kOk) {
      EXPECT_LT((leg.foot_position(sol) - p).norm(), 1e-9);
      EXPECT_LT((sol - q).norm(), 1e-9) << q.transpose();
      ++round_trips;
    }
  }
  EXPECT_GT(round_trips, 250);
}

// foot_and_jacobian's trig: the set's cosines and sines of the kinematics' angles (signs and
// offsets applied), bit for bit std::cos / std::sin of them, on our legs (mirrored signs) and on
// the odd leg (knee axis along -y, thigh and shank angled at q = 0).
TEST(LegKinematics, TrigIsTheSetOfTheKinematicsAngles) {
  std::vector<LegGeometry> legs;
  const RobotModel model = *testing::load_quadruped();
  std::string why;
  for (const char* foot : kFeet) {
    LegGeometry g;
    ASSERT_EQ(leg_geometry_from_model(model, "trunk", foot, &g, &why), Status::kOk) << why;
    legs.push_back(g);
  }
  RobotModel odd;
  ASSERT_EQ(model_from_urdf_string(kOddLeg, "", "", &odd, &why), Status::kOk) << why;
  LegGeometry g_odd;
  ASSERT_EQ(leg_geometry_from_model(odd, "trunk", "foot", &g_odd, &why), Status::kOk) << why;
  EXPECT_NE(g_odd.a_shank - g_odd.a_thigh, 0.0);
  legs.push_back(g_odd);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-3.2, 3.2);
  for (const LegGeometry& g : legs) {
    const LegKinematics leg(g);
    for (int k = 0; k < 1000; ++k) {
      const Eigen::Vector3d q(u(rng), u(rng), u(rng));
      Eigen::Vector3d p;
      Eigen::Matrix3d J;
      LegKinematics::Trig trig;
      leg.foot_and_jacobian(q, &p, &J, &trig);
      const Eigen::Vector3d qs = q.cwiseProduct(g.sign);
      const double p1 = qs[1] + g.a_thigh, p12 = qs[1] + qs[2] + g.a_shank;
      EXPECT_EQ(trig.c0, std::cos(qs[0]));
      EXPECT_EQ(trig.s0, std::sin(qs[0]));
      EXPECT_EQ(trig.c1, std::cos(p1));
      EXPECT_EQ(trig.s1, std::sin(p1));
      EXPECT_EQ(trig.c12, std::cos(p12));
      EXPECT_EQ(trig.s12, std::sin(p12));
      EXPECT_EQ(trig.pitch_axis, Eigen::Vector3d(0.0, trig.c0, trig.s0));
    }
  }
}

// A foot point off the foot link's origin (ANYmal's contact sphere sits 23 mm up the shank; here
// also off to the side and forward, on the odd leg): the closed form tracks that point, equal to
// KDL's FK of the foot frame applied to the offset, and IK round-trips through it.
TEST(LegKinematics, FootOffsetIsTrackedAsTheFootPoint) {
  RobotModel model;
  std::string why;
  ASSERT_EQ(model_from_urdf_string(kOddLeg, "", "", &model, &why), Status::kOk) << why;
  const Eigen::Vector3d offset(0.004, -0.006, 0.023);  // [m] foot link frame
  LegGeometry g, g0;
  ASSERT_EQ(leg_geometry_from_model(model, "trunk", "foot", &g, &why, KneeDirection::kAuto, offset),
            Status::kOk) << why;
  ASSERT_EQ(leg_geometry_from_model(model, "trunk", "foot", &g0, &why), Status::kOk) << why;
  EXPECT_NEAR(g.l_abd, g0.l_abd + offset.y(), 1e-12);  // the foot frame is not turned here
  EXPECT_LT(g.l_shank, g0.l_shank);                    // the point is up the shank
  const LegKinematics leg(g);
  KDL::Chain chain;
  ASSERT_TRUE(model.tree().getChain("trunk", "foot", chain));
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::JntArray qk(3);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int round_trips = 0;
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector3d q(0.5 * u(rng), 0.6 * u(rng), -1.3 + 1.1 * u(rng));
    for (int j = 0; j < 3; ++j) qk(j) = q[j];
    KDL::Frame T;
    fk.JntToCart(qk, T);
    const KDL::Vector expected = T * KDL::Vector(offset.x(), offset.y(), offset.z());
    const Eigen::Vector3d p = leg.foot_position(q);
    ASSERT_LT((p - Eigen::Vector3d(expected.x(), expected.y(), expected.z())).norm(), 1e-12) << q.transpose();
    Eigen::Vector3d sol = Eigen::Vector3d::Zero();
    if (leg.inverse(p, sol) == Status::kOk) {
      EXPECT_LT((sol - q).norm(), 1e-9) << q.transpose();
      ++round_trips;
    }
  }
  EXPECT_GT(round_trips, 150);
}

// A zero offset is the link origin exactly: the same geometry, bit for bit, as without one.
TEST(LegKinematics, ZeroFootOffsetLeavesTheGeometryUnchanged) {
  const RobotModel model = *testing::load_quadruped();
  for (const char* foot : kFeet) {
    LegGeometry a, b;
    std::string why;
    ASSERT_EQ(leg_geometry_from_model(model, "trunk", foot, &a, &why), Status::kOk) << why;
    ASSERT_EQ(leg_geometry_from_model(model, "trunk", foot, &b, &why, KneeDirection::kAuto,
                                      Eigen::Vector3d::Zero()), Status::kOk) << why;
    EXPECT_EQ(a.abd_origin, b.abd_origin);
    EXPECT_EQ(a.l_abd, b.l_abd);
    EXPECT_EQ(a.h_abd, b.h_abd);
    EXPECT_EQ(a.l_thigh, b.l_thigh);
    EXPECT_EQ(a.l_shank, b.l_shank);
    EXPECT_EQ(a.a_thigh, b.a_thigh);
    EXPECT_EQ(a.a_shank, b.a_shank);
  }
}

// An offset as long as the shank (a unit or frame mistake) or not finite is refused, named.
TEST(LegKinematics, RejectsAFootOffsetBeyondTheShank) {
  const RobotModel model = *testing::load_quadruped();
  LegGeometry g;
  std::string why;
  EXPECT_EQ(leg_geometry_from_model(model, "trunk", "FL_foot", &g, &why, KneeDirection::kAuto,
                                    Eigen::Vector3d(0, 0, 0.25)), Status::kModelError);
  EXPECT_NE(why.find("foot_offset"), std::string::npos) << why;
  why.clear();
  EXPECT_EQ(leg_geometry_from_model(model, "trunk", "FL_foot", &g, &why, KneeDirection::kAuto,
                                    Eigen::Vector3d(0, std::nan(""), 0)), Status::kModelError);
  EXPECT_NE(why.find("foot_offset"), std::string::npos) << why;
}

// A leg whose hip frame is turned a quarter turn about z, written as real URDFs write it
// (rpy 1.57079: 6.3e-6 rad short of pi/2), its joint axes given in that frame: its axes lie
// 6.3e-6 rad off the trunk's x, y, y. `hip_rpy` replaces the turn (a canted hip).
std::string rotated_hip_leg(const char* hip_rpy) {
  const std::string inertial = R"(<inertial><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial>)";
  return std::string(R"(<robot name="rounded">
  <link name="trunk"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="abd" type="revolute"><parent link="trunk"/><child link="hip"/><origin xyz="0.2 0.05 0" rpy=")") +
         hip_rpy + R"("/>
    <axis xyz="0 -1 0"/><limit lower="-1" upper="1" effort="5" velocity="10"/></joint>
  <link name="hip">)" + inertial + R"(</link>
  <joint name="pitch" type="revolute"><parent link="hip"/><child link="thigh"/><origin xyz="0.05 0 0"/>
    <axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="5" velocity="10"/></joint>
  <link name="thigh">)" + inertial + R"(</link>
  <joint name="knee" type="revolute"><parent link="thigh"/><child link="shank"/><origin xyz="0 0 -0.2"/>
    <axis xyz="1 0 0"/><limit lower="-2.6" upper="-0.1" effort="5" velocity="10"/></joint>
  <link name="shank">)" + inertial + R"(</link>
  <joint name="foot_fixed" type="fixed"><parent link="shank"/><child link="foot"/><origin xyz="0 0 -0.2"/></joint>
  <link name="foot"/>
</robot>)";
}

TEST(LegKinematics, AxesOffByARoundedQuarterTurnAreTheTrunksAxes) {
  RobotModel model;
  std::string why;
  ASSERT_EQ(model_from_urdf_string(rotated_hip_leg("0 0 1.57079"), "", "", &model, &why),
            Status::kOk) << why;
  LegGeometry g;
  ASSERT_EQ(leg_geometry_from_model(model, "trunk", "foot", &g, &why), Status::kOk) << why;
  const LegKinematics leg(g);
  KDL::Chain chain;
  ASSERT_TRUE(model.tree().getChain("trunk", "foot", chain));
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::JntArray qk(3);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 100; ++k) {
    const Eigen::Vector3d q(0.5 * u(rng), 0.6 * u(rng), -1.3 + 1.1 * u(rng));
    for (int j = 0; j < 3; ++j) qk(j) = q[j];
    KDL::Frame T;
    fk.JntToCart(qk, T);
    // 6.3e-6 rad on levers of 0.45 m at most: a few micrometres, not more.
    EXPECT_LT((leg.foot_position(q) - Eigen::Vector3d(T.p.x(), T.p.y(), T.p.z())).norm(), 1e-5);
  }
}

TEST(LegKinematics, ACantedHipIsRefusedByNameAndAngle) {
  RobotModel model;
  std::string why;
  ASSERT_EQ(model_from_urdf_string(rotated_hip_leg("0 0.1 1.5707963267948966"), "", "", &model, &why),
            Status::kOk) << why;
  LegGeometry g;
  EXPECT_EQ(leg_geometry_from_model(model, "trunk", "foot", &g, &why), Status::kModelError);
  EXPECT_NE(why.find("joint 'pitch' (hip pitch)"), std::string::npos) << why;
  EXPECT_NE(why.find("5.73 deg off the trunk's y axis"), std::string::npos) << why;
}

TEST(LegKinematics, RejectsAnArmChain) {
  RobotModel ur5;
  std::string why;
  ASSERT_EQ(model_from_urdf_file(std::string(KILOLOOP_MODELS_DIR) + "/ur5/ur5.urdf", "", "", &ur5, &why),
            Status::kOk);
  LegGeometry g;
  EXPECT_EQ(leg_geometry_from_model(ur5, "base_link", "tool0", &g, &why), Status::kModelError);
  EXPECT_NE(why.find("tool0"), std::string::npos);
}

}  // namespace
}  // namespace kiloloop
