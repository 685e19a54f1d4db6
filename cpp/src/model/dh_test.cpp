#include "kiloloop/model/dh.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "kiloloop/dynamics/dynamics.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {

struct ClosedForm {
  Eigen::Matrix2d M;
  Eigen::Vector2d c, g;
};

// Spong, "Robot Modeling and Control", the two-link planar arm with point masses at the tips.
ClosedForm planar_closed_form(const testing::PlanarArm& a, const Eigen::Vector2d& q,
                              const Eigen::Vector2d& qd, double g0) {
  const double c2 = std::cos(q[1]), s2 = std::sin(q[1]);
  ClosedForm r;
  r.M(0, 0) = a.m1 * a.l1 * a.l1 + a.m2 * (a.l1 * a.l1 + a.l2 * a.l2 + 2 * a.l1 * a.l2 * c2);
  r.M(0, 1) = r.M(1, 0) = a.m2 * (a.l2 * a.l2 + a.l1 * a.l2 * c2);
  r.M(1, 1) = a.m2 * a.l2 * a.l2;
  const double h = a.m2 * a.l1 * a.l2 * s2;
  r.c << -h * (2 * qd[0] * qd[1] + qd[1] * qd[1]), h * qd[0] * qd[0];
  r.g << (a.m1 + a.m2) * g0 * a.l1 * std::cos(q[0]) + a.m2 * g0 * a.l2 * std::cos(q[0] + q[1]),
      a.m2 * g0 * a.l2 * std::cos(q[0] + q[1]);
  return r;
}

std::vector<DhLink> modified_table(const testing::PlanarArm& a) {
  std::vector<DhLink> links(2);
  links[0].mass = a.m1;
  links[0].com = Eigen::Vector3d(a.l1, 0, 0);  // frame 1 is at joint 1; the mass at link 1's tip
  links[1].a = a.l1;                           // a_{1}: joint 2 sits l1 along x1
  links[1].mass = a.m2;
  links[1].com = Eigen::Vector3d(a.l2, 0, 0);
  return links;
}

class DhPlanar : public ::testing::TestWithParam<DhConvention> {};

TEST_P(DhPlanar, MatchesClosedFormDynamics) {
  const testing::PlanarArm arm;
  const auto table = GetParam() == DhConvention::kStandard ? arm.table() : modified_table(arm);
  auto model = std::make_shared<RobotModel>();
  std::string why;
  ASSERT_EQ(model_from_dh(table, GetParam(), model.get(), &why), Status::kOk) << why;
  ASSERT_EQ(model->nq(), 2);
  const double g0 = 9.81;
  Dynamics dyn;
  ASSERT_EQ(Dynamics::configure(model, Eigen::Vector3d(0, -g0, 0), &dyn, &why), Status::kOk) << why;
  const unsigned seed = 7;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-3, 3);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector2d q(u(rng), u(rng)), qd(u(rng), u(rng));
    const ClosedForm ref = planar_closed_form(arm, q, qd, g0);
    Eigen::MatrixXd M(2, 2);
    Eigen::VectorXd c(2), g(2);
    ASSERT_EQ(dyn.mass_matrix(q, M), Status::kOk);
    ASSERT_EQ(dyn.coriolis(q, qd, c), Status::kOk);
    ASSERT_EQ(dyn.gravity(q, g), Status::kOk);
    EXPECT_LT((M - ref.M).cwiseAbs().maxCoeff(), 1e-12) << "seed " << seed << " k " << k;
    EXPECT_LT((c - ref.c).cwiseAbs().maxCoeff(), 1e-12) << "seed " << seed << " k " << k;
    EXPECT_LT((g - ref.g).cwiseAbs().maxCoeff(), 1e-12) << "seed " << seed << " k " << k;
    // Tip position: standard DH ends at link 2's tip; modified ends at joint 2 (+ l2 along x2).
    Eigen::Matrix4d T;
    ASSERT_EQ(dyn.forward_kinematics(q, T), Status::kOk);
    const Eigen::Vector3d tip = T.block<3, 1>(0, 3) +
        (GetParam() == DhConvention::kModified ? Eigen::Vector3d(T.block<3, 1>(0, 0) * arm.l2)
                                              : Eigen::Vector3d::Zero());
    EXPECT_NEAR(tip.x(), arm.l1 * std::cos(q[0]) + arm.l2 * std::cos(q[0] + q[1]), 1e-12);
    EXPECT_NEAR(tip.y(), arm.l1 * std::sin(q[0]) + arm.l2 * std::sin(q[0] + q[1]), 1e-12);
  }
}

INSTANTIATE_TEST_SUITE_P(Conventions, DhPlanar,
                         ::testing::Values(DhConvention::kStandard, DhConvention::kModified));

TEST(Dh, RejectsAsymmetricInertia) {
  std::vector<DhLink> links(1);
  links[0].mass = 1.0;
  links[0].inertia << 1, 0.5, 0, 0, 1, 0, 0, 0, 1;
  RobotModel model;
  std::string why;
  EXPECT_EQ(model_from_dh(links, DhConvention::kStandard, &model, &why), Status::kModelError);
  EXPECT_NE(why.find("asymmetric"), std::string::npos) << why;
}

// The UR5 URDF in models/ is written so that its FK equals the published standard-DH product.
TEST(Dh, Ur5TableMatchesUrdfKinematics) {
  const double pi = M_PI;
  const double a[6] = {0, -0.425, -0.39225, 0, 0, 0};
  const double alpha[6] = {pi / 2, 0, 0, pi / 2, -pi / 2, 0};
  const double d[6] = {0.089159, 0, 0, 0.10915, 0.09465, 0.0823};
  std::vector<DhLink> links(6);
  for (int i = 0; i < 6; ++i) {
    links[i].a = a[i];
    links[i].alpha = alpha[i];
    links[i].d = d[i];
    links[i].mass = 1.0;
    links[i].inertia = Eigen::Matrix3d::Identity() * 1e-3;
  }
  auto dh = std::make_shared<RobotModel>();
  std::string why;
  ASSERT_EQ(model_from_dh(links, DhConvention::kStandard, dh.get(), &why), Status::kOk) << why;
  Dynamics dyn_dh, dyn_urdf;
  ASSERT_EQ(Dynamics::configure(dh, {0, 0, -9.81}, &dyn_dh, &why), Status::kOk);
  ASSERT_EQ(Dynamics::configure(testing::load_ur5(), {0, 0, -9.81}, &dyn_urdf, &why), Status::kOk);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-pi, pi);
  for (int k = 0; k < 100; ++k) {
    Eigen::VectorXd q(6);
    for (int i = 0; i < 6; ++i) q[i] = u(rng);
    Eigen::Matrix4d T1, T2;
    ASSERT_EQ(dyn_dh.forward_kinematics(q, T1), Status::kOk);
    ASSERT_EQ(dyn_urdf.forward_kinematics(q, T2), Status::kOk);
    EXPECT_LT((T1 - T2).cwiseAbs().maxCoeff(), 1e-12) << "seed 11 k " << k;
  }
}

}  // namespace
}  // namespace kiloloop
