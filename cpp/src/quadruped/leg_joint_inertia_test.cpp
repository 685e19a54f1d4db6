// LegJointInertia: H(q) equals KDL's ChainDynParam::JntToMass at poses away from standing, with no
// allocation, and folding the leg lowers the hip pitch's inertia.
#include "kiloloop/quadruped/leg_joint_inertia.hpp"

#include <gtest/gtest.h>
#include <kdl/chaindynparam.hpp>

#include "alloc_counter.hpp"
#include "kiloloop/quadruped/free_leg_inertia.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {

Eigen::Matrix3d kdl_mass(const KDL::Chain& chain, const Eigen::Vector3d& q) {
  KDL::ChainDynParam dyn(chain, KDL::Vector::Zero());
  KDL::JntArray jq(3);
  KDL::JntSpaceInertiaMatrix H(3);
  for (int k = 0; k < 3; ++k) jq(k) = q[k];
  dyn.JntToMass(jq, H);
  return Eigen::Matrix3d(H.data);
}

TEST(LegJointInertia, MatchesKdlAtAnyPose) {
  const RobotModelPtr model = testing::load_quadruped();
  for (const char* foot : {"FL_foot", "RR_foot"}) {
    const KDL::Chain chain = leg_chain(*model, "trunk", foot);
    LegJointInertia leg;
    ASSERT_TRUE(leg.configure(chain));
    for (const Eigen::Vector3d& q : {Eigen::Vector3d(0.0, 0.9, -1.8), Eigen::Vector3d(0.3, 1.4, -2.4),
                                    Eigen::Vector3d(-0.2, 0.2, -0.6)}) {
      const Eigen::Matrix3d expected = kdl_mass(chain, q);
      EXPECT_LT((leg.at(q) - expected).norm(), 1e-12 * (1.0 + expected.norm())) << foot << " " << q.transpose();
    }
  }
}

TEST(LegJointInertia, FoldingTheLegLowersTheHipInertiaWithoutAllocating) {
  LegJointInertia leg;
  ASSERT_TRUE(leg.configure(leg_chain(*testing::load_quadruped(), "trunk", "FL_foot")));
  Eigen::Matrix3d stand, folded;
  {
    testing::AllocationScope scope;
    stand = leg.at(Eigen::Vector3d(0.0, 0.9, -1.8));
    folded = leg.at(Eigen::Vector3d(0.0, 1.2, -2.6));
    EXPECT_EQ(scope.count(), 0u);
  }
  EXPECT_LT(folded(1, 1), stand(1, 1));
  EXPECT_GT(folded.determinant(), 0.0);
}

TEST(LegJointInertia, RefusesAChainWithoutThreeJoints) {
  KDL::Chain chain;
  chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotX)));
  LegJointInertia leg;
  EXPECT_FALSE(leg.configure(chain));
}

}  // namespace
}  // namespace kiloloop
