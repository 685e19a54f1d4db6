// FloatingBaseRne against KDL's fixed-base RNE (base at rest), against Newton's law for the whole
// arm (the root wrench balances the arm's momentum rate), and allocation-free. The moving-base
// cross-check against MuJoCo's mj_inverse is in tests/test_aerial_dynamics.py.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>

#include "aerial_model.hpp"
#include "alloc_counter.hpp"
#include "kiloloop/aerial/floating_base_rne.hpp"
#include "kiloloop/dynamics/dynamics.hpp"

namespace kiloloop {
namespace {

FloatingBaseRne make_rne(RobotModelPtr model) {
  FloatingBaseRne rne;
  std::string why;
  EXPECT_EQ(FloatingBaseRne::configure(model, &rne, &why), Status::kOk) << why;
  return rne;
}

TEST(FloatingBaseRne, BaseAtRestEqualsKdlFixedBaseRne) {
  const RobotModelPtr model = testing::load_aerial();
  ASSERT_EQ(model->nq(), 3);
  FloatingBaseRne rne = make_rne(model);
  // KDL's own solver as the oracle (Dynamics::inverse_dynamics runs ChainRne, as rne does).
  const KDL::Chain chain = model->chain();
  KDL::ChainIdSolver_RNE kdl(chain, KDL::Vector(0, 0, -9.81));
  const KDL::Wrenches none(chain.getNrOfSegments(), KDL::Wrench::Zero());
  KDL::JntArray kq(3), kqd(3), kqdd(3), ktau(3);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  BaseMotion rest;  // level, at rest: the accelerometer reads +g up
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Vector3d q(u(rng), u(rng), u(rng)), qd(u(rng), u(rng), u(rng)),
        qdd(u(rng), u(rng), u(rng));
    Eigen::VectorXd tau(3), tau_kdl(3);
    Vector6d W;
    Eigen::Vector3d tip;
    ASSERT_EQ(rne.compute(q, qd, qdd, rest, tau, &W, &tip), Status::kOk);
    kq.data = q;
    kqd.data = qd;
    kqdd.data = qdd;
    ASSERT_GE(kdl.CartToJnt(kq, kqd, kqdd, none, ktau), 0);
    tau_kdl = ktau.data;
    EXPECT_LT((tau - tau_kdl).cwiseAbs().maxCoeff(), 1e-12) << "trial " << trial;
    // The end effector from the same pass, against KDL's forward kinematics at q.
    KDL::Frame f;
    ASSERT_GE(KDL::ChainFkSolverPos_recursive(chain).JntToCart(kq, f), 0);
    EXPECT_LT((tip - Eigen::Vector3d(f.p.x(), f.p.y(), f.p.z())).cwiseAbs().maxCoeff(), 1e-12) << "trial " << trial;
  }
}

TEST(FloatingBaseRne, StaticArmHangsItsWeightOnTheBody) {
  const RobotModelPtr model = testing::load_aerial();
  FloatingBaseRne rne = make_rne(model);
  Eigen::VectorXd tau(3);
  Vector6d W;
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  ASSERT_EQ(rne.compute(zero, zero, zero, BaseMotion{}, tau, &W), Status::kOk);
  // 0.30 kg of arm straight below the body: the body holds it up with 0.30 g, no torque.
  EXPECT_NEAR(W[2], 0.30 * 9.81, 1e-9);
  EXPECT_NEAR(W.head<2>().norm() + W.tail<3>().norm(), 0.0, 1e-9);
  EXPECT_LT(tau.norm(), 1e-9);
}

TEST(FloatingBaseRne, RootForceIsTheArmsMomentumRate) {
  // Free fall with the body spinning and the arm moving: the body's force on the arm equals the
  // total mass times the arm CoM's acceleration minus gravity. Checked by finite differences of
  // the CoM position computed by forward kinematics of the segments.
  const RobotModelPtr model = testing::load_aerial();
  FloatingBaseRne rne = make_rne(model);
  Eigen::VectorXd tau(3);
  Vector6d W;
  BaseMotion base;
  base.specific_force.setZero();  // free fall, not spinning: then a finite difference is easy
  Eigen::Vector3d q(0.3, -0.7, 1.1), qd(0.5, -0.4, 0.9), qdd(0.2, 0.3, -0.6);
  ASSERT_EQ(rne.compute(q, qd, qdd, base, tau, &W), Status::kOk);
  auto com = [&](const Eigen::Vector3d& qq) {
    const KDL::Chain& c = model->chain();
    KDL::Frame T = KDL::Frame::Identity();
    KDL::RigidBodyInertia total = KDL::RigidBodyInertia::Zero();
    int j = 0;
    for (unsigned i = 0; i < c.getNrOfSegments(); ++i) {
      const bool moving = c.getSegment(i).getJoint().getType() != KDL::Joint::Fixed;
      T = T * c.getSegment(i).pose(moving ? qq[j++] : 0.0);
      total = total + T * c.getSegment(i).getInertia();
    }
    const KDL::Vector p = total.getCOG() * total.getMass();
    return Eigen::Vector3d(p.x(), p.y(), p.z());  // first moment [kg m]
  };
  const double h = 1e-4;
  // Second derivative of the first moment along q(t) = q + qd t + qdd t^2 / 2.
  auto path = [&](double t) { return com(q + qd * t + 0.5 * qdd * t * t); };
  const Eigen::Vector3d acc = (path(h) - 2.0 * path(0.0) + path(-h)) / (h * h);
  EXPECT_LT((W.head<3>() - acc).norm(), 1e-5) << W.head<3>().transpose() << " vs "
                                              << acc.transpose();
}

TEST(FloatingBaseRne, FirstMomentOfTheHangingAndTheRaisedArm) {
  const RobotModelPtr model = testing::load_aerial();
  FloatingBaseRne rne = make_rne(model);
  Eigen::Vector3d moment;
  double mass = 0.0;
  ASSERT_EQ(rne.first_moment(Eigen::Vector3d::Zero(), &moment, &mass), Status::kOk);
  EXPECT_NEAR(mass, 0.30, 1e-12);
  // Hanging: link1 0.05 at -0.075, link2 0.15 at -0.18, link3 0.08 at -0.345, ee 0.02 at -0.42.
  const double z = -(0.05 * 0.075 + 0.15 * 0.18 + 0.08 * 0.345 + 0.02 * 0.42);
  EXPECT_LT((moment - Eigen::Vector3d(0, 0, z)).norm(), 1e-12);
  // Shoulder at +90 deg: everything below the shoulder swings to -x.
  ASSERT_EQ(rne.first_moment(Eigen::Vector3d(0, M_PI / 2, 0), &moment, &mass), Status::kOk);
  EXPECT_NEAR(moment.x(), -(0.15 * 0.09 + 0.08 * 0.255 + 0.02 * 0.33), 1e-12);
  EXPECT_EQ(rne.first_moment(Eigen::Vector2d::Zero(), &moment, &mass), Status::kBadSize);
}

TEST(FloatingBaseRne, BadInputsGiveStatusAndZeros) {
  const RobotModelPtr model = testing::load_aerial();
  FloatingBaseRne rne = make_rne(model);
  Eigen::VectorXd tau = Eigen::VectorXd::Ones(3);
  Vector6d W = Vector6d::Ones();
  Eigen::Vector3d q(0.1, 0.2, 0.3), nan_q(0.1, std::nan(""), 0.3);
  EXPECT_EQ(rne.compute(nan_q, q, q, BaseMotion{}, tau, &W), Status::kNonFiniteMeasurement);
  EXPECT_EQ(tau.norm() + W.norm(), 0.0);
  Eigen::VectorXd short_q = Eigen::VectorXd::Zero(2);
  EXPECT_EQ(rne.compute(short_q, q, q, BaseMotion{}, tau, &W), Status::kBadSize);
  BaseMotion bad;
  bad.alpha.x() = std::nan("");
  EXPECT_EQ(rne.compute(q, q, q, bad, tau, &W), Status::kNonFiniteMeasurement);
  FloatingBaseRne none;
  EXPECT_EQ(none.compute(q, q, q, BaseMotion{}, tau, &W), Status::kNotConfigured);
}

TEST(FloatingBaseRne, IsAllocationFree) {
  const RobotModelPtr model = testing::load_aerial();
  FloatingBaseRne rne = make_rne(model);
  Eigen::VectorXd tau(3);
  Vector6d W;
  Eigen::Vector3d q(0.1, 0.2, 0.3), qd(0.4, 0.5, 0.6), tip, moment;
  double mass;
  BaseMotion base;
  base.omega << 0.1, -0.2, 0.3;
  testing::AllocationScope scope;
  for (int k = 0; k < 10000; ++k) {
    q[k % 3] += 1e-6;
    rne.compute(q, qd, q, base, tau, &W, &tip);
    rne.first_moment(q, &moment, &mass);
  }
  EXPECT_EQ(scope.count(), 0u);
}

}  // namespace
}  // namespace kiloloop
