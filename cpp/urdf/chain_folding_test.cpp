// Chain folding on real-looking descriptions: a gripper beyond the tip (fixed palm, prismatic
// fingers, one a mimic), a camera mast branching off link 2 with a pan joint, a continuous wrist.
// Oracle: KDL's tree RNE over the whole tree with the off-chain joints held at their locked
// positions (zero velocity and acceleration) gives the chain joints' torques of the reduced model.
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include "kiloloop/dynamics/dynamics.hpp"
#include "kiloloop/urdf/urdf_loader.hpp"

namespace kiloloop {
namespace {

std::string inertial(double m, const char* xyz) {
  return std::string("<inertial><origin xyz=\"") + xyz + "\" rpy=\"0.1 -0.2 0.3\"/><mass value=\"" +
         std::to_string(m) +
         "\"/><inertia ixx=\"0.02\" iyy=\"0.03\" izz=\"0.025\" ixy=\"0.001\" ixz=\"-0.002\" iyz=\"0.0015\"/></inertial>";
}

std::string arm_urdf() {
  return "<robot name=\"folded\">"
         "<link name=\"base\"/>"
         "<link name=\"l1\">" + inertial(3.0, "0 0 0.1") + "</link>"
         "<link name=\"l2\">" + inertial(2.5, "0.15 0 0") + "</link>"
         "<link name=\"l3\">" + inertial(1.2, "0.1 0.01 0") + "</link>"
         "<link name=\"tool0\"/>"
         "<link name=\"palm\">" + inertial(0.6, "0 0 0.03") + "</link>"
         "<link name=\"finger_a\">" + inertial(0.1, "0 0.01 0.04") + "</link>"
         "<link name=\"finger_b\">" + inertial(0.1, "0 -0.01 0.04") + "</link>"
         "<link name=\"mast\">" + inertial(0.4, "0 0 0.1") + "</link>"
         "<link name=\"camera\">" + inertial(0.3, "0.02 0 0") + "</link>"
         "<joint name=\"j1\" type=\"revolute\"><parent link=\"base\"/><child link=\"l1\"/>"
         "<origin xyz=\"0 0 0.2\"/><axis xyz=\"0 0 1\"/><limit lower=\"-3\" upper=\"3\" velocity=\"2\" effort=\"80\"/></joint>"
         "<joint name=\"j2\" type=\"revolute\"><parent link=\"l1\"/><child link=\"l2\"/>"
         "<origin xyz=\"0 0.05 0.2\" rpy=\"1.5707963 0 0\"/><axis xyz=\"0 0 1\"/><limit lower=\"-3\" upper=\"3\" velocity=\"2\" effort=\"80\"/></joint>"
         "<joint name=\"j3\" type=\"continuous\"><parent link=\"l2\"/><child link=\"l3\"/>"
         "<origin xyz=\"0.35 0 0\" rpy=\"0 0.3 0\"/><axis xyz=\"0.6 0 0.8\"/></joint>"
         "<joint name=\"flange\" type=\"fixed\"><parent link=\"l3\"/><child link=\"tool0\"/>"
         "<origin xyz=\"0.25 0 0\" rpy=\"0 1.5707963 0\"/></joint>"
         "<joint name=\"palm_joint\" type=\"fixed\"><parent link=\"tool0\"/><child link=\"palm\"/>"
         "<origin xyz=\"0 0 0.02\" rpy=\"0 0 0.7\"/></joint>"
         "<joint name=\"finger_a_joint\" type=\"prismatic\"><parent link=\"palm\"/><child link=\"finger_a\"/>"
         "<origin xyz=\"0 0 0.06\"/><axis xyz=\"0 1 0\"/><limit lower=\"0\" upper=\"0.04\" velocity=\"0.2\" effort=\"20\"/></joint>"
         "<joint name=\"finger_b_joint\" type=\"prismatic\"><parent link=\"palm\"/><child link=\"finger_b\"/>"
         "<origin xyz=\"0 0 0.06\"/><axis xyz=\"0 -1 0\"/><limit lower=\"0\" upper=\"0.04\" velocity=\"0.2\" effort=\"20\"/>"
         "<mimic joint=\"finger_a_joint\"/></joint>"
         "<joint name=\"mast_joint\" type=\"fixed\"><parent link=\"l2\"/><child link=\"mast\"/>"
         "<origin xyz=\"0.1 0.08 0\" rpy=\"-1.5707963 0 0\"/></joint>"
         "<joint name=\"pan\" type=\"revolute\"><parent link=\"mast\"/><child link=\"camera\"/>"
         "<origin xyz=\"0 0 0.2\"/><axis xyz=\"0 0 1\"/><limit lower=\"-2\" upper=\"2\" velocity=\"1\" effort=\"5\"/></joint>"
         "</robot>";
}

const std::map<std::string, double> kLocked = {{"finger_a_joint", 0.03}, {"finger_b_joint", 0.02}, {"pan", 0.8}};

TEST(ChainFolding, ChainTorquesEqualTheTreeWithOffChainJointsLocked) {
  const std::string xml = arm_urdf();
  auto model = std::make_shared<RobotModel>();
  std::string why;
  ASSERT_EQ(model_from_urdf_string(xml, "base", "tool0", kLocked, model.get(), &why), Status::kOk) << why;
  ASSERT_EQ(model->nq(), 3);
  // The oracle's tree: the same URDF as KDL sees it, unfolded.
  const KDL::Tree& tree = model->tree();
  const KDL::Vector g(0.3, -0.5, -9.81);
  KDL::TreeIdSolver_RNE tree_rne(tree, g);
  Dynamics dyn;
  ASSERT_EQ(Dynamics::configure(model, Eigen::Vector3d(g.x(), g.y(), g.z()), &dyn, &why), Status::kOk) << why;
  std::map<std::string, int> qnr;
  for (const auto& [name, el] : tree.getSegments())
    if (GetTreeElementSegment(el).getJoint().getType() != KDL::Joint::None)
      qnr[GetTreeElementSegment(el).getJoint().getName()] = GetTreeElementQNr(el);
  const unsigned n = tree.getNrOfJoints();
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int k = 0; k < 50; ++k) {
    Eigen::VectorXd q(3), qd(3), qdd(3), tau(3);
    KDL::JntArray tq(n), tqd(n), tqdd(n), ttau(n);
    for (const auto& [joint, value] : kLocked) tq(qnr.at(joint)) = value;
    for (int i = 0; i < 3; ++i) {
      q[i] = u(rng), qd[i] = u(rng), qdd[i] = u(rng);
      const int j = qnr.at(model->joint_names()[i]);
      tq(j) = q[i], tqd(j) = qd[i], tqdd(j) = qdd[i];
    }
    ASSERT_GE(tree_rne.CartToJnt(tq, tqd, tqdd, KDL::WrenchMap{}, ttau), 0);
    ASSERT_EQ(dyn.inverse_dynamics(q, qd, qdd, tau), Status::kOk);
    for (int i = 0; i < 3; ++i) {
      const double ref = ttau(qnr.at(model->joint_names()[i]));
      EXPECT_NEAR(tau[i], ref, 1e-10 * (1.0 + std::abs(ref))) << "seed 41 k " << k << " joint " << i;
    }
  }
}

TEST(ChainFolding, RecordsWhatWasFoldedOntoWhichLink) {
  RobotModel model;
  std::string why;
  ASSERT_EQ(model_from_urdf_string(arm_urdf(), "base", "tool0", kLocked, &model, &why), Status::kOk) << why;
  std::map<std::string, std::pair<std::string, double>> folded;
  for (const FoldedLink& f : model.folded()) folded[f.link] = {f.onto, f.mass};
  ASSERT_EQ(folded.size(), 5u);
  EXPECT_EQ(folded["palm"].first, "tool0");
  EXPECT_EQ(folded["finger_b"].first, "tool0");
  EXPECT_DOUBLE_EQ(folded["finger_b"].second, 0.1);
  EXPECT_EQ(folded["mast"].first, "l2");
  EXPECT_EQ(folded["camera"].first, "l2");
  // The tree is kept as loaded; the chain carries the folded mass.
  double chain_mass = 0.0;
  for (const auto& seg : model.chain().segments) chain_mass += seg.getInertia().getMass();
  EXPECT_NEAR(chain_mass, model.total_mass(), 1e-12);
  EXPECT_NEAR(model.total_mass(), 3.0 + 2.5 + 1.2 + 0.6 + 0.2 + 0.4 + 0.3, 1e-12);
}

TEST(ChainFolding, AMimicJointInTheChainIsRefusedNamingIt) {
  RobotModel model;
  std::string why;
  EXPECT_EQ(model_from_urdf_string(arm_urdf(), "base", "finger_b", &model, &why), Status::kModelError);
  EXPECT_NE(why.find("mimic joint 'finger_b_joint'"), std::string::npos) << why;
  // Without a tip every joint would be controlled, the mimic one too.
  EXPECT_EQ(model_from_urdf_string(arm_urdf(), "", "", &model, &why), Status::kModelError);
  EXPECT_NE(why.find("'finger_b_joint'"), std::string::npos) << why;
}

TEST(ChainFolding, ChainGivenTipToRootOrAcrossBranchesIsRefused) {
  RobotModel model;
  std::string why;
  EXPECT_EQ(model_from_urdf_string(arm_urdf(), "tool0", "l1", &model, &why), Status::kModelError);
  EXPECT_NE(why.find("tip->root"), std::string::npos) << why;
  EXPECT_NE(why.find("'l1' is an ancestor of root link 'tool0'"), std::string::npos) << why;
  EXPECT_EQ(model_from_urdf_string(arm_urdf(), "camera", "tool0", &model, &why), Status::kModelError);
  EXPECT_NE(why.find("different branches"), std::string::npos) << why;
}

TEST(ChainFolding, UnknownLinksAndLockedJointsAreNamed) {
  RobotModel model;
  std::string why;
  EXPECT_EQ(model_from_urdf_string(arm_urdf(), "base", "tool9", &model, &why), Status::kModelError);
  EXPECT_NE(why.find("tip link 'tool9' is not in the model (links: "), std::string::npos) << why;
  EXPECT_NE(why.find("camera"), std::string::npos) << why;  // a few names to spot the typo
  EXPECT_EQ(model_from_urdf_string(arm_urdf(), "base", "tool0", {{"pann", 0.1}}, &model, &why),
            Status::kModelError);
  EXPECT_NE(why.find("locked joint 'pann' is not a joint"), std::string::npos) << why;
  EXPECT_EQ(model_from_urdf_string(arm_urdf(), "base", "tool0", {{"j2", 0.1}}, &model, &why),
            Status::kModelError);
  EXPECT_NE(why.find("'j2' is in the chain"), std::string::npos) << why;
}

}  // namespace
}  // namespace kiloloop
