// The one builder (model/model_description.hpp) against kdl_parser, the construction it replaces:
// for every robot in models/, every segment kdl_parser builds exists in the description's tree
// with the same joint, tip frame, inertia and children, compared bit for bit (memcmp, not a
// tolerance); and a model rebuilt from a copied description has the same dynamics with ==.
#include "kiloloop/model/model_description.hpp"

#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>
#include <kdl_parser/kdl_parser.hpp>

#include "kiloloop/dynamics/dynamics.hpp"
#include "kiloloop/urdf/urdf_description.hpp"
#include "kiloloop/urdf/urdf_loader.hpp"

namespace kiloloop {
namespace {

std::string read(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

bool same_bits(const double* a, const double* b, int n) { return std::memcmp(a, b, 8 * n) == 0; }

void expect_same_frame(const KDL::Frame& a, const KDL::Frame& b, const std::string& what) {
  EXPECT_TRUE(same_bits(a.p.data, b.p.data, 3) && same_bits(a.M.data, b.M.data, 9)) << what;
}

class DescriptionVsKdlParser : public ::testing::TestWithParam<const char*> {};

TEST_P(DescriptionVsKdlParser, EverySegmentIsBitIdentical) {
  const std::string path = std::string(KILOLOOP_MODELS_DIR) + "/" + GetParam();
  const std::string xml = read(path);
  KDL::Tree oracle;
  ASSERT_TRUE(kdl_parser::treeFromString(xml, oracle));
  UrdfDescription urdf;
  std::string why;
  ASSERT_EQ(description_from_urdf_string(xml, &urdf, &why), Status::kOk) << why;
  KDL::Tree tree;
  ASSERT_EQ(tree_from_description(urdf.description(), &tree, &why), Status::kOk) << why;

  const std::string oracle_root = oracle.getRootSegment()->first;
  int compared = 0;
  for (const auto& [name, element] : oracle.getSegments()) {
    if (name == oracle_root) continue;  // kdl_parser's root is no segment (ours may be: restored)
    const auto it = tree.getSegment(name);
    ASSERT_NE(it, tree.getSegments().end()) << name;
    const KDL::Segment& a = GetTreeElementSegment(element);
    const KDL::Segment& b = GetTreeElementSegment(it->second);
    EXPECT_EQ(a.getJoint().getName(), b.getJoint().getName()) << name;
    EXPECT_EQ(a.getJoint().getType(), b.getJoint().getType()) << name;
    const KDL::Vector ax = a.getJoint().JointAxis(), bx = b.getJoint().JointAxis();
    const KDL::Vector ao = a.getJoint().JointOrigin(), bo = b.getJoint().JointOrigin();
    EXPECT_TRUE(same_bits(ax.data, bx.data, 3) && same_bits(ao.data, bo.data, 3)) << name;
    expect_same_frame(a.getFrameToTip(), b.getFrameToTip(), name + " tip frame");
    const double am = a.getInertia().getMass(), bm = b.getInertia().getMass();
    const KDL::Vector ac = a.getInertia().getCOG(), bc = b.getInertia().getCOG();
    const KDL::RotationalInertia ai = a.getInertia().getRotationalInertia();
    const KDL::RotationalInertia bi = b.getInertia().getRotationalInertia();
    EXPECT_TRUE(same_bits(&am, &bm, 1) && same_bits(ac.data, bc.data, 3) &&
                same_bits(ai.data, bi.data, 9)) << name << " inertia";
    std::vector<std::string> ac_names, bc_names;
    for (const auto& c : GetTreeElementChildren(element)) ac_names.push_back(c->first);
    for (const auto& c : GetTreeElementChildren(it->second)) bc_names.push_back(c->first);
    EXPECT_EQ(ac_names, bc_names) << name << " children";
    ++compared;
  }
  EXPECT_GT(compared, 3);
}

INSTANTIATE_TEST_SUITE_P(Models, DescriptionVsKdlParser,
                         ::testing::Values("ur5/ur5.urdf", "panda/panda.urdf",
                                           "quadruped/quadruped.urdf",
                                           "aerial_manipulator/aerial_manipulator.urdf"));

// A copied description (what an exported header holds: the same numbers, other storage) gives a
// model whose mass matrix, gravity and Coriolis equal the URDF-loaded model's with ==.
TEST(ModelDescription, CopiedDescriptionHasIdenticalDynamics) {
  const std::string path = std::string(KILOLOOP_MODELS_DIR) + "/ur5/ur5.urdf";
  UrdfDescription urdf;
  std::string why;
  ASSERT_EQ(description_from_urdf_string(read(path), &urdf, &why), Status::kOk) << why;
  const std::vector<SegmentSpec> copy(urdf.description().segments,
                                      urdf.description().segments + urdf.description().segment_count);
  ModelDescription copied = urdf.description();
  copied.segments = copy.data();

  auto loaded = std::make_shared<RobotModel>(), rebuilt = std::make_shared<RobotModel>();
  ASSERT_EQ(model_from_urdf_file(path, "base_link", "tool0", loaded.get(), &why), Status::kOk) << why;
  ASSERT_EQ(model_from_description(copied, "base_link", "tool0", {}, rebuilt.get(), &why),
            Status::kOk) << why;
  Dynamics a, b;
  const Eigen::Vector3d g(0, 0, -9.81);
  ASSERT_EQ(Dynamics::configure(loaded, g, &a, &why), Status::kOk);
  ASSERT_EQ(Dynamics::configure(rebuilt, g, &b, &why), Status::kOk);
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  const int nq = a.nq();
  Eigen::MatrixXd Ma(nq, nq), Mb(nq, nq);
  Eigen::VectorXd q(nq), qd(nq), ga(nq), gb(nq), ca(nq), cb(nq);
  for (int trial = 0; trial < 20; ++trial) {
    for (int j = 0; j < nq; ++j) q[j] = u(rng), qd[j] = u(rng);
    a.mass_matrix(q, Ma);
    b.mass_matrix(q, Mb);
    a.gravity(q, ga);
    b.gravity(q, gb);
    a.coriolis(q, qd, ca);
    b.coriolis(q, qd, cb);
    EXPECT_TRUE(Ma == Mb && ga == gb && ca == cb) << "trial " << trial;
  }
}

}  // namespace
}  // namespace kiloloop
