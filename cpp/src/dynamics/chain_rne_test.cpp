#include "kiloloop/dynamics/chain_rne.hpp"

#include <random>

#include <gtest/gtest.h>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>

#include "alloc_counter.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {

KDL::RigidBodyInertia body(double m, double cx, double cy, double cz) {
  return KDL::RigidBodyInertia(m, KDL::Vector(cx, cy, cz),
                               KDL::RotationalInertia(0.02 * m, 0.03 * m, 0.025 * m, 0.001, -0.002, 0.0015));
}

// Every kind of segment KDL chains hold: a fixed base, revolute joints about an arbitrary axis
// through an offset origin and about the frame axes, a prismatic joint, a massless fixed tip,
// rotor inertia, tilted tip frames.
KDL::Chain mixed_chain() {
  KDL::Chain c;
  const KDL::Rotation tilt = KDL::Rotation::RPY(0.3, -0.2, 0.7);
  c.addSegment(KDL::Segment("base", KDL::Joint("fixed", KDL::Joint::Fixed),
                            KDL::Frame(KDL::Vector(0.0, 0.0, 0.1)), body(2.0, 0.0, 0.0, 0.05)));
  KDL::Vector axis(0.2, -0.5, 0.8);
  axis.Normalize();
  c.addSegment(KDL::Segment("a", KDL::Joint("ja", KDL::Vector(0.01, 0.02, 0.0), axis, KDL::Joint::RotAxis, 1, 0, 0.05),
                            KDL::Frame(tilt, KDL::Vector(0.1, 0.0, 0.3)), body(1.5, 0.05, 0.01, 0.15)));
  c.addSegment(KDL::Segment("b", KDL::Joint("jb", KDL::Joint::RotY),
                            KDL::Frame(KDL::Vector(0.0, 0.05, 0.4)), body(1.0, 0.0, 0.02, 0.2)));
  c.addSegment(KDL::Segment("c", KDL::Joint("jc", KDL::Vector(0.0, 0.0, 0.1), KDL::Vector(0, 0, 1),
                                            KDL::Joint::TransAxis, 1, 0, 0.2),
                            KDL::Frame(tilt.Inverse(), KDL::Vector(0.0, 0.0, 0.05)), body(0.7, 0.01, 0.0, 0.03)));
  c.addSegment(KDL::Segment("d", KDL::Joint("jd", KDL::Joint::RotX), KDL::Frame(KDL::Vector(0.1, 0.0, 0.0)),
                            body(0.3, 0.05, 0.0, 0.0)));
  c.addSegment(KDL::Segment("tool", KDL::Joint("tool_fixed", KDL::Joint::Fixed),
                            KDL::Frame(KDL::Vector(0.0, 0.0, 0.08))));
  return c;
}

// ChainRne against KDL's ChainIdSolver_RNE (the oracle) on random states and gravity vectors,
// and its gravity-only pass against KDL's ChainDynParam::JntToGravity.
void expect_equal_to_kdl(const KDL::Chain& chain, unsigned seed) {
  ChainRne rne;
  std::string why;
  ASSERT_EQ(ChainRne::configure(chain, &rne, &why), Status::kOk) << why;
  const int n = static_cast<int>(chain.getNrOfJoints());
  ASSERT_EQ(rne.nq(), n);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  KDL::JntArray q(n), qd(n), qdd(n), tau_kdl(n), g_kdl(n);
  KDL::Wrenches none(chain.getNrOfSegments(), KDL::Wrench::Zero());
  Eigen::VectorXd tau(n), g(n);
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d gravity(3.0 * u(rng), 3.0 * u(rng), -9.81 + 2.0 * u(rng));
    for (int j = 0; j < n; ++j) {
      q(j) = 3.0 * u(rng);
      qd(j) = 4.0 * u(rng);
      qdd(j) = 10.0 * u(rng);
    }
    KDL::ChainIdSolver_RNE kdl(chain, KDL::Vector(gravity.x(), gravity.y(), gravity.z()));
    ASSERT_GE(kdl.CartToJnt(q, qd, qdd, none, tau_kdl), 0);
    rne.inverse_dynamics(q.data.data(), qd.data.data(), qdd.data.data(), gravity, tau.data());
    Eigen::Matrix3d last_rot;
    Eigen::Vector3d last_pos, last_position;
    rne.last_tip_pose(&last_rot, &last_pos);
    rne.last_tip_position(&last_position);
    const double scale = 1.0 + tau_kdl.data.cwiseAbs().maxCoeff();
    EXPECT_LT((tau - tau_kdl.data).cwiseAbs().maxCoeff(), 1e-12 * scale) << "seed " << seed << " k " << k;

    KDL::ChainDynParam dyn(chain, KDL::Vector(gravity.x(), gravity.y(), gravity.z()));
    ASSERT_GE(dyn.JntToGravity(q, g_kdl), 0);
    rne.gravity_torque(q.data.data(), gravity, g.data());
    EXPECT_LT((g - g_kdl.data).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + g_kdl.data.cwiseAbs().maxCoeff()))
        << "seed " << seed << " k " << k;

    // Tip pose against KDL's recursive FK (the trailing fixed tool frame included), and the
    // first moment against each segment's centre of mass placed by KDL's FK to that segment.
    KDL::ChainFkSolverPos_recursive fk(chain);
    KDL::Frame tip;
    ASSERT_GE(fk.JntToCart(q, tip), 0);
    Eigen::Matrix3d rot;
    Eigen::Vector3d pos;
    rne.tip_pose(q.data.data(), &rot, &pos);
    for (int r = 0; r < 3; ++r) {
      EXPECT_NEAR(pos(r), tip.p(r), 1e-12) << "seed " << seed << " k " << k;
      EXPECT_NEAR(last_pos(r), tip.p(r), 1e-12) << "seed " << seed << " k " << k;
      EXPECT_NEAR(last_position(r), tip.p(r), 1e-12) << "seed " << seed << " k " << k;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(last_rot(r, c), tip.M(r, c), 1e-12) << "seed " << seed << " k " << k;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(rot(r, c), tip.M(r, c), 1e-12) << "seed " << seed << " k " << k;
    }
    Eigen::Vector3d moment_kdl = Eigen::Vector3d::Zero(), moment;
    double mass_kdl = 0.0, mass = 0.0;
    for (unsigned i = 0; i < chain.getNrOfSegments(); ++i) {
      KDL::Frame f;
      ASSERT_GE(fk.JntToCart(q, f, static_cast<int>(i) + 1), 0);
      const KDL::RigidBodyInertia& I = chain.getSegment(i).getInertia();
      const KDL::Vector c = f * I.getCOG();
      moment_kdl += I.getMass() * Eigen::Vector3d(c.x(), c.y(), c.z());
      mass_kdl += I.getMass();
    }
    rne.first_moment(q.data.data(), &moment, &mass);
    EXPECT_LT((moment - moment_kdl).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + mass_kdl)) << "seed " << seed << " k " << k;
    EXPECT_NEAR(mass, mass_kdl, 1e-12 * mass_kdl);
  }
}

TEST(ChainRne, EqualsKdlOnTheUr5) { expect_equal_to_kdl(testing::load_ur5()->chain(), 11); }

TEST(ChainRne, EqualsKdlOnEveryJointKind) { expect_equal_to_kdl(mixed_chain(), 12); }

TEST(ChainRne, RefusesAJointScaleItDoesNotModel) {
  KDL::Chain c;
  c.addSegment(KDL::Segment("a", KDL::Joint("ja", KDL::Joint::RotZ, 2.0), KDL::Frame(KDL::Vector(0, 0, 0.1)),
                            body(1.0, 0.0, 0.0, 0.05)));
  ChainRne rne;
  std::string why;
  EXPECT_EQ(ChainRne::configure(c, &rne, &why), Status::kModelError);
  EXPECT_NE(why.find("ja"), std::string::npos) << why;
}

TEST(ChainRne, IsAllocationFree) {
  ChainRne rne;
  std::string why;
  ASSERT_EQ(ChainRne::configure(mixed_chain(), &rne, &why), Status::kOk) << why;
  double q[4] = {0.1, 0.2, 0.3, 0.4}, qd[4] = {1, 2, 3, 4}, qdd[4] = {-1, 0, 1, 2}, tau[4];
  const Eigen::Vector3d gravity(0.0, 0.0, -9.81);
  Eigen::Matrix3d rot;
  Eigen::Vector3d pos, moment;
  double mass;
  testing::AllocationScope scope;
  for (int k = 0; k < 1000; ++k) {
    rne.inverse_dynamics(q, qd, qdd, gravity, tau);
    rne.gravity_torque(q, gravity, tau);
    rne.tip_pose(q, &rot, &pos);
    rne.last_tip_pose(&rot, &pos);
    rne.last_tip_position(&pos);
    rne.first_moment(q, &moment, &mass);
  }
  EXPECT_EQ(scope.count(), 0u);
}

}  // namespace
}  // namespace kiloloop
