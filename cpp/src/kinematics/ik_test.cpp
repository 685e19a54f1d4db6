// Kinematics for IK: compiled chain FK/Jacobian vs KDL (through Dynamics), the UR closed form,
// the numeric LM solver and their composition. Seeds are printed in the failure messages.
#include <cmath>
#include "test_values.hpp"
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"
#include "kiloloop/dynamics/dynamics.hpp"
#include "kiloloop/kinematics/arm_ik.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {


RobotModelPtr load_panda() {
  auto model = std::make_shared<RobotModel>();
  std::string why;
  EXPECT_EQ(model_from_urdf_file(std::string(KILOLOOP_MODELS_DIR) + "/panda/panda.urdf", "", "",
                                 model.get(), &why),
            Status::kOk)
      << why;
  return model;
}

Eigen::VectorXd random_in_limits(const RobotModel& m, std::mt19937& rng) {
  Eigen::VectorXd q(m.nq());
  for (int i = 0; i < m.nq(); ++i) {
    const double lo = std::max(m.lower()[i], -kPi), hi = std::min(m.upper()[i], kPi);
    q[i] = std::uniform_real_distribution<double>(lo, hi)(rng);
  }
  return q;
}

Eigen::Isometry3d fk(ChainKinematics& kin, const Eigen::VectorXd& q) {
  Eigen::Isometry3d T;
  kin.forward(q, T);
  return T;
}

class ChainKinematicsVsKdl : public ::testing::TestWithParam<int> {};

TEST_P(ChainKinematicsVsKdl, PoseAndJacobianMatchKdl) {
  const RobotModelPtr model = GetParam() == 0 ? testing::load_ur5() : load_panda();
  ChainKinematics kin;
  Dynamics dyn;
  std::string why;
  ASSERT_EQ(ChainKinematics::configure(*model, &kin, &why), Status::kOk) << why;
  ASSERT_EQ(Dynamics::configure(model, {0, 0, -9.81}, &dyn, &why), Status::kOk) << why;
  std::mt19937 rng(3);
  for (int k = 0; k < 200; ++k) {
    const Eigen::VectorXd q = random_in_limits(*model, rng);
    Eigen::Matrix4d T_kdl;
    Eigen::MatrixXd J_kdl(6, model->nq()), J(6, model->nq());
    Eigen::Isometry3d T;
    ASSERT_EQ(dyn.forward_kinematics(q, T_kdl), Status::kOk);
    ASSERT_EQ(dyn.jacobian(q, J_kdl), Status::kOk);
    kin.forward_jacobian(q, T, J);
    EXPECT_LT((T.matrix() - T_kdl).cwiseAbs().maxCoeff(), 1e-12) << "seed 3 k " << k;
    EXPECT_LT((J - J_kdl).cwiseAbs().maxCoeff(), 1e-12) << "seed 3 k " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(Ur5AndPanda, ChainKinematicsVsKdl, ::testing::Values(0, 1));

TEST(UrAnalyticIk, AllSolutionsReachTheTargetAndIncludeTheTrueOne) {
  const RobotModelPtr model = testing::load_ur5();
  UrAnalyticIk ik;
  ChainKinematics kin;
  std::string why;
  ASSERT_EQ(UrAnalyticIk::from_model(*model, &ik, &why), Status::kOk) << why;
  ASSERT_EQ(ChainKinematics::configure(*model, &kin, &why), Status::kOk);
  EXPECT_NEAR(ik.parameters().d1, 0.089159, 1e-12);
  EXPECT_NEAR(ik.parameters().a2, -0.425, 1e-12);
  EXPECT_NEAR(ik.parameters().a3, -0.39225, 1e-12);
  EXPECT_NEAR(ik.parameters().d6, 0.0823, 1e-12);
  std::mt19937 rng(17);
  int eight = 0;
  const int trials = 1000;
  for (int k = 0; k < trials; ++k) {
    const Eigen::VectorXd q_true = random_in_limits(*model, rng);
    const Eigen::VectorXd seed = random_in_limits(*model, rng);
    const Eigen::Isometry3d target = fk(kin, q_true);
    UrAnalyticIk::Solutions sols;
    int count = 0;
    ASSERT_EQ(ik.solve(target, Eigen::Matrix<double, 6, 1>(seed), sols, &count), Status::kOk)
        << "seed 17 k " << k;
    eight += count == 8;
    double found = 1e9, prev = -1.0;
    for (int s = 0; s < count; ++s) {
      const Eigen::VectorXd q = sols.col(s);
      const Vector6d e = pose_error(target, fk(kin, q));
      EXPECT_LT(e.head<3>().norm(), 1e-9) << "seed 17 k " << k << " solution " << s;
      EXPECT_LT(e.tail<3>().norm(), 1e-9) << "seed 17 k " << k << " solution " << s;
      EXPECT_TRUE((q.array() >= model->lower().array()).all() &&
                  (q.array() <= model->upper().array()).all());
      const double d = (q - seed).norm();
      EXPECT_GE(d, prev) << "not sorted nearest-to-seed first, seed 17 k " << k;
      prev = d;
      // The configuration that produced the target is one of them, up to 2 pi per joint.
      Eigen::VectorXd diff = q - q_true;
      for (int i = 0; i < 6; ++i) diff[i] = std::remainder(diff[i], 2 * kPi);
      found = std::min(found, diff.cwiseAbs().maxCoeff());
    }
    EXPECT_LT(found, 1e-7) << "seed 17 k " << k;
  }
  // Most random poses have all 8 (the others lose branches the elbow cannot reach).
  std::printf("seed 17: %d of %d poses with 8 solutions\n", eight, trials);
  EXPECT_GT(eight, trials / 2);
}

TEST(UrAnalyticIk, RefusesANonUrChainAndUnreachableTargets) {
  UrAnalyticIk ik;
  std::string why;
  EXPECT_EQ(UrAnalyticIk::from_model(*load_panda(), &ik, &why), Status::kModelError);
  ASSERT_EQ(UrAnalyticIk::from_model(*testing::load_ur5(), &ik, &why), Status::kOk);
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translation() << 2.0, 0.0, 0.5;
  UrAnalyticIk::Solutions sols;
  int count = -1;
  EXPECT_EQ(ik.solve(far, Eigen::Matrix<double, 6, 1>::Zero(), sols, &count), Status::kUnreachable);
  EXPECT_EQ(count, 0);
  far.translation().x() = std::nan("");
  EXPECT_EQ(ik.solve(far, Eigen::Matrix<double, 6, 1>::Zero(), sols, &count),
            Status::kNonFiniteReference);
}

struct SolveStats {
  int success = 0, trials = 0;
};

SolveStats solve_random(const RobotModelPtr& model, ArmIk& ik, unsigned seed, int trials) {
  ChainKinematics kin;
  std::string why;
  EXPECT_EQ(ChainKinematics::configure(*model, &kin, &why), Status::kOk);
  std::mt19937 rng(seed);
  SolveStats st;
  Eigen::VectorXd q(model->nq());
  for (int k = 0; k < trials; ++k) {
    const Eigen::VectorXd q_true = random_in_limits(*model, rng);
    const Eigen::VectorXd q_seed = random_in_limits(*model, rng);
    const Eigen::Isometry3d target = fk(kin, q_true);
    const Status s = ik.solve(target, q_seed, q);
    EXPECT_TRUE(q.allFinite());
    EXPECT_TRUE((q.array() >= model->lower().array()).all() &&
                (q.array() <= model->upper().array()).all())
        << "seed " << seed << " k " << k;
    const Vector6d e = pose_error(target, fk(kin, q));
    const bool within = e.head<3>().norm() <= 1e-6 && e.tail<3>().norm() <= 1e-6;
    // The status tells the truth about the tolerances.
    EXPECT_EQ(s == Status::kOk, within) << "seed " << seed << " k " << k;
    st.success += within;
    ++st.trials;
  }
  return st;
}

TEST(NumericIk, SolvesRandomPandaPosesFromRandomSeeds) {
  const RobotModelPtr model = load_panda();
  ArmIk ik;
  std::string why;
  ASSERT_EQ(ArmIk::configure(ArmIkConfig{}, *model, &ik, &why), Status::kOk) << why;
  EXPECT_FALSE(ik.has_analytic());
  const SolveStats st = solve_random(model, ik, 29, 500);
  EXPECT_GE(st.success, 495) << "seed 29: " << st.success << " of " << st.trials;
}

TEST(NumericIk, UrNumericOnlyAndWithAnalyticSeed) {
  const RobotModelPtr model = testing::load_ur5();
  std::string why;
  ArmIk hybrid, numeric;
  ArmIkConfig cfg;
  ASSERT_EQ(ArmIk::configure(cfg, *model, &hybrid, &why), Status::kOk) << why;
  EXPECT_TRUE(hybrid.has_analytic());
  cfg.use_analytic = false;
  ASSERT_EQ(ArmIk::configure(cfg, *model, &numeric, &why), Status::kOk) << why;
  EXPECT_FALSE(numeric.has_analytic());
  EXPECT_EQ(solve_random(model, hybrid, 31, 500).success, 500);
  EXPECT_GE(solve_random(model, numeric, 31, 500).success, 495);
}

// Targets on the UR5's singular sets (wrist q5 = 0, stretched elbow q3 = 0, both) from nearby
// seeds: Gauss-Newton steps blow up there; the adaptive damping keeps LM converging.
TEST(NumericIk, ConvergesOnSingularUrTargets) {
  const RobotModelPtr model = testing::load_ur5();
  std::string why;
  ArmIkConfig cfg;
  for (bool analytic : {true, false}) {
    cfg.use_analytic = analytic;
    ArmIk ik;
    ChainKinematics kin;
    ASSERT_EQ(ArmIk::configure(cfg, *model, &ik, &why), Status::kOk);
    ASSERT_EQ(ChainKinematics::configure(*model, &kin, &why), Status::kOk);
    std::mt19937 rng(59);
    std::normal_distribution<double> noise(0.0, 0.3);
    Eigen::VectorXd q(6);
    for (int k = 0; k < 300; ++k) {
      Eigen::VectorXd q_true = random_in_limits(*model, rng);
      if (k % 3 != 1) q_true[4] = 0.0;
      if (k % 3 != 0) q_true[2] = 0.0;
      Eigen::VectorXd seed = q_true;
      for (int i = 0; i < 6; ++i) seed[i] += noise(rng);
      const Eigen::Isometry3d target = fk(kin, q_true);
      EXPECT_EQ(ik.solve(target, seed, q), Status::kOk)
          << "seed 59 k " << k << (analytic ? " analytic" : " numeric");
      const Vector6d e = pose_error(target, fk(kin, q));
      EXPECT_LE(e.head<3>().norm(), 1e-6);
      EXPECT_LE(e.tail<3>().norm(), 1e-6);
    }
  }
}

// A UR5 whose joint origins are off by a millimetre and a few milliradians (as after a
// calibration): no longer exactly UR, so the closed form only seeds; LM refines to 1e-6.
TEST(ArmIk, AnalyticSeedPlusRefinementOnANearlyUrChain) {
  std::ifstream f(testing::ur5_urdf_path());
  std::string xml((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const std::pair<const char*, const char*> edits[] = {
      {"<origin xyz=\"-0.425 0 0\" rpy=\"0 0 0\"/>",
       "<origin xyz=\"-0.4242 0.0006 0.0007\" rpy=\"0.002 -0.003 0.001\"/>"},
      {"<origin xyz=\"-0.39225 0 0\" rpy=\"0 0 0\"/>",
       "<origin xyz=\"-0.3930 -0.0004 0.0005\" rpy=\"0.001 0.002 -0.002\"/>"},
      {"<origin xyz=\"0 0 0.0823\" rpy=\"0 0 0\"/>", "<origin xyz=\"0.0005 0 0.0831\" rpy=\"0 0.002 0\"/>"}};
  for (const auto& [from, to] : edits) {
    const auto pos = xml.find(from);
    ASSERT_NE(pos, std::string::npos) << from;
    xml.replace(pos, std::strlen(from), to);
  }
  auto model = std::make_shared<RobotModel>();
  std::string why;
  ASSERT_EQ(model_from_urdf_string(xml, "", "", model.get(), &why), Status::kOk) << why;
  UrAnalyticIk exact;
  EXPECT_EQ(UrAnalyticIk::from_model(*model, &exact, &why), Status::kModelError);
  ArmIk hybrid, numeric;
  ArmIkConfig cfg;
  ASSERT_EQ(ArmIk::configure(cfg, *model, &hybrid, &why), Status::kOk);
  ASSERT_TRUE(hybrid.has_analytic());
  EXPECT_GT(hybrid.analytic_deviation(), 1e-4);
  EXPECT_LT(hybrid.analytic_deviation(), 1e-2);
  cfg.use_analytic = false;
  ASSERT_EQ(ArmIk::configure(cfg, *model, &numeric, &why), Status::kOk);
  ChainKinematics kin;
  ASSERT_EQ(ChainKinematics::configure(*model, &kin, &why), Status::kOk);
  std::mt19937 rng(61);
  Eigen::VectorXd q(6);
  long hybrid_iterations = 0, numeric_iterations = 0;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Isometry3d target = fk(kin, random_in_limits(*model, rng));
    const Eigen::VectorXd seed = random_in_limits(*model, rng);
    ASSERT_EQ(hybrid.solve(target, seed, q), Status::kOk) << "seed 61 k " << k;
    hybrid_iterations += hybrid.report().iterations;
    EXPECT_GT(hybrid.report().iterations, 0);  // the closed form alone is not within 1e-6
    const Vector6d e = pose_error(target, fk(kin, q));
    EXPECT_LE(e.head<3>().norm(), 1e-6);
    EXPECT_LE(e.tail<3>().norm(), 1e-6);
    numeric.solve(target, seed, q);
    numeric_iterations += numeric.report().iterations;
  }
  std::printf("seed 61: mean LM iterations, analytic seed %.2f vs numeric only %.2f\n",
              hybrid_iterations / 300.0, numeric_iterations / 300.0);
  EXPECT_LT(hybrid_iterations * 3, numeric_iterations);
}

TEST(NumericIk, TaskWeightsFreeTheOrientation) {
  const RobotModelPtr model = load_panda();
  NumericIkConfig cfg;
  cfg.weights << 1, 1, 1, 0, 0, 0;
  NumericIk ik;
  ChainKinematics kin;
  std::string why;
  ASSERT_EQ(NumericIk::configure(cfg, *model, &ik, &why), Status::kOk) << why;
  ASSERT_EQ(ChainKinematics::configure(*model, &kin, &why), Status::kOk);
  std::mt19937 rng(37);
  Eigen::VectorXd q(7);
  for (int k = 0; k < 100; ++k) {
    const Eigen::VectorXd q_true = random_in_limits(*model, rng);
    Eigen::Isometry3d target = fk(kin, q_true);
    // An arbitrary orientation: unreachable together with the position in general, ignored here.
    target.linear() = Eigen::AngleAxisd(1.0, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    const Eigen::VectorXd seed = random_in_limits(*model, rng);
    ASSERT_EQ(ik.solve(target, seed, q), Status::kOk) << "seed 37 k " << k;
    EXPECT_LT((fk(kin, q).translation() - target.translation()).norm(), 1e-6);
  }
}

TEST(NumericIk, BadInputGivesAStatusAndAFiniteInLimitOutput) {
  const RobotModelPtr model = load_panda();
  NumericIk ik;
  std::string why;
  ASSERT_EQ(NumericIk::configure(NumericIkConfig{}, *model, &ik, &why), Status::kOk);
  Eigen::VectorXd q(7), seed = (model->lower() + model->upper()) / 2;
  Eigen::Isometry3d target = Eigen::Isometry3d::Identity();
  target.translation() << std::nan(""), 0, 0;
  EXPECT_EQ(ik.solve(target, seed, q), Status::kNonFiniteReference);
  EXPECT_TRUE(q.allFinite());
  target.translation() << 0.4, 0, 0.4;
  Eigen::VectorXd bad = seed;
  bad[2] = INFINITY;
  EXPECT_EQ(ik.solve(target, bad, q), Status::kNonFiniteMeasurement);
  EXPECT_TRUE(q.allFinite());
  Eigen::VectorXd short_q(6);
  EXPECT_EQ(ik.solve(target, seed, short_q), Status::kBadSize);
  // Out of reach: the budget runs out, the best iterate is returned.
  target.translation() << 3.0, 0, 0.4;
  EXPECT_EQ(ik.solve(target, seed, q), Status::kIterationLimit);
  EXPECT_TRUE(q.allFinite());
  EXPECT_TRUE((q.array() >= model->lower().array()).all() &&
              (q.array() <= model->upper().array()).all());
  EXPECT_EQ(ik.report().iterations, NumericIkConfig{}.max_iterations);
  NumericIkConfig cfg;
  cfg.position_tolerance = 0.0;
  EXPECT_EQ(NumericIk::configure(cfg, *model, &ik, &why), Status::kInvalidConfig);
  EXPECT_NE(why.find("tolerance"), std::string::npos) << why;
}

TEST(NumericIk, SolveAllocatesNothingAndIsDeterministic) {
  for (int robot = 0; robot < 2; ++robot) {
    const RobotModelPtr model = robot == 0 ? testing::load_ur5() : load_panda();
    ArmIk ik;
    ChainKinematics kin;
    std::string why;
    ASSERT_EQ(ArmIk::configure(ArmIkConfig{}, *model, &ik, &why), Status::kOk);
    ASSERT_EQ(ChainKinematics::configure(*model, &kin, &why), Status::kOk);
    std::mt19937 rng(41);
    std::vector<Eigen::Isometry3d> targets;
    std::vector<Eigen::VectorXd> seeds;
    for (int k = 0; k < 300; ++k) {
      targets.push_back(fk(kin, random_in_limits(*model, rng)));
      seeds.push_back(random_in_limits(*model, rng));
    }
    Eigen::MatrixXd first(model->nq(), 300), second(model->nq(), 300);
    Eigen::VectorXd q(model->nq());
    {
      testing::AllocationScope scope;
      for (int k = 0; k < 300; ++k) {
        ik.solve(targets[k], seeds[k], q);
        first.col(k) = q;
      }
      EXPECT_EQ(scope.count(), 0u) << "robot " << robot;
    }
    for (int k = 0; k < 300; ++k) {
      ik.solve(targets[k], seeds[k], q);
      second.col(k) = q;
    }
    EXPECT_EQ(std::memcmp(first.data(), second.data(), sizeof(double) * first.size()), 0);
  }
}

}  // namespace
}  // namespace kiloloop
