#include "kiloloop/dynamics/dynamics.hpp"

#include <random>

#include <Eigen/Eigenvalues>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {

class Ur5Dynamics : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    ASSERT_EQ(Dynamics::configure(testing::load_ur5(), {0, 0, -9.81}, &dyn, &why), Status::kOk)
        << why;
  }
  Eigen::VectorXd random_vector(std::mt19937& rng, double scale) {
    std::uniform_real_distribution<double> u(-scale, scale);
    Eigen::VectorXd v(6);
    for (int i = 0; i < 6; ++i) v[i] = u(rng);
    return v;
  }
  Dynamics dyn;
};

TEST_F(Ur5Dynamics, InverseDynamicsEqualsMassCoriolisGravity) {
  const unsigned seed = 1234;
  std::mt19937 rng(seed);
  Eigen::VectorXd tau(6), c(6), g(6);
  Eigen::MatrixXd M(6, 6);
  for (int k = 0; k < 500; ++k) {
    const Eigen::VectorXd q = random_vector(rng, 3.0), qd = random_vector(rng, 2.0),
                          qdd = random_vector(rng, 5.0);
    ASSERT_EQ(dyn.inverse_dynamics(q, qd, qdd, tau), Status::kOk);
    ASSERT_EQ(dyn.mass_matrix(q, M), Status::kOk);
    ASSERT_EQ(dyn.coriolis(q, qd, c), Status::kOk);
    ASSERT_EQ(dyn.gravity(q, g), Status::kOk);
    EXPECT_LT((tau - (M * qdd + c + g)).cwiseAbs().maxCoeff(), 1e-10) << "seed " << seed;
    EXPECT_LT((M - M.transpose()).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M).eigenvalues().minCoeff(), 0.0);
  }
}

// The Jacobian maps qd to the tip twist: compare with a finite difference of FK.
TEST_F(Ur5Dynamics, JacobianMatchesFiniteDifferenceOfFk) {
  std::mt19937 rng(5);
  Eigen::MatrixXd J(6, 6);
  Eigen::Matrix4d T0, T1;
  for (int k = 0; k < 50; ++k) {
    const Eigen::VectorXd q = random_vector(rng, 3.0);
    ASSERT_EQ(dyn.jacobian(q, J), Status::kOk);
    ASSERT_EQ(dyn.forward_kinematics(q, T0), Status::kOk);
    for (int j = 0; j < 6; ++j) {
      const double h = 1e-7;
      Eigen::VectorXd qh = q;
      qh[j] += h;
      ASSERT_EQ(dyn.forward_kinematics(qh, T1), Status::kOk);
      const Eigen::Vector3d v = (T1.block<3, 1>(0, 3) - T0.block<3, 1>(0, 3)) / h;
      const Eigen::Matrix3d W = (T1.block<3, 3>(0, 0) - T0.block<3, 3>(0, 0)) / h *
                                T0.block<3, 3>(0, 0).transpose();
      const Eigen::Vector3d w(W(2, 1), W(0, 2), W(1, 0));
      EXPECT_LT((J.col(j).head<3>() - v).norm(), 1e-5);
      EXPECT_LT((J.col(j).tail<3>() - w).norm(), 1e-5);
    }
  }
}

TEST_F(Ur5Dynamics, EveryCallIsAllocationFree) {
  std::mt19937 rng(3);
  const Eigen::VectorXd q = random_vector(rng, 3.0), qd = random_vector(rng, 2.0),
                        qdd = random_vector(rng, 5.0);
  Eigen::VectorXd tau(6);
  Eigen::MatrixXd M(6, 6), J(6, 6);
  Eigen::Matrix4d T;
  dyn.inverse_dynamics(q, qd, qdd, tau);  // warm-up
  testing::AllocationScope scope;
  for (int k = 0; k < 10000; ++k) {
    dyn.inverse_dynamics(q, qd, qdd, tau);
    dyn.mass_matrix(q, M);
    dyn.coriolis(q, qd, tau);
    dyn.gravity(q, tau);
    dyn.forward_kinematics(q, T);
    dyn.jacobian(q, J);
  }
  EXPECT_EQ(scope.count(), 0u);
}

TEST_F(Ur5Dynamics, BadInputsReturnStatusAndLeaveOutputsAlone) {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(6), tau = Eigen::VectorXd::Constant(6, 7.0);
  Eigen::VectorXd short_q = Eigen::VectorXd::Zero(5);
  EXPECT_EQ(dyn.gravity(short_q, tau), Status::kBadSize);
  q[2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(dyn.gravity(q, tau), Status::kNonFiniteMeasurement);
  EXPECT_EQ(tau, Eigen::VectorXd::Constant(6, 7.0));
  q[2] = 0.0;
  Eigen::VectorXd qdd = Eigen::VectorXd::Zero(6);
  qdd[0] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(dyn.inverse_dynamics(q, q, qdd, tau), Status::kNonFiniteReference);
  Eigen::VectorXd small_tau(3);
  EXPECT_EQ(dyn.gravity(q, small_tau), Status::kBadSize);
  Dynamics unconfigured;
  EXPECT_EQ(unconfigured.gravity(q, tau), Status::kNotConfigured);
}

TEST(Dynamics, RefusesABranchingTree) {
  RobotModel branching;
  std::string why;
  const char* urdf = R"(<robot name="y"><link name="a"/><link name="b"><inertial><mass value="1"/>
    <inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link><link name="c"><inertial>
    <mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <joint name="j1" type="continuous"><parent link="a"/><child link="b"/></joint>
    <joint name="j2" type="continuous"><parent link="a"/><child link="c"/></joint></robot>)";
  ASSERT_EQ(model_from_urdf_string(urdf, "", "", &branching, &why), Status::kOk) << why;
  Dynamics dyn;
  EXPECT_EQ(Dynamics::configure(std::make_shared<RobotModel>(branching), {0, 0, -9.81}, &dyn, &why),
            Status::kModelError);
  EXPECT_NE(why.find("serial chain"), std::string::npos);
}

}  // namespace
}  // namespace kiloloop
