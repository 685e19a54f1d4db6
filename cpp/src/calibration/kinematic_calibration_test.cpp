// Kinematic calibration of a UR5 whose true geometry differs from the nominal DH table (a
// perturbed KDL chain, not the identified form): identification from 0.1 mm-noisy positions,
// checked on held-out configurations.
#include <cmath>
#include "test_values.hpp"
#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>
#include <kdl/chain.hpp>
#include <kdl/frames.hpp>

#include "kiloloop/calibration/kinematic_calibration.hpp"
#include "kiloloop/kinematics/chain_kinematics.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {


KinematicParameters ur5_nominal() {
  KinematicParameters k;
  std::string why;
  // A target 5 cm out from the flange, as a tracker reflector would be.
  EXPECT_EQ(KinematicParameters::from_ur_model(*testing::load_ur5(), Eigen::Vector3d(0, 0, 0.05), &k, &why),
            Status::kOk) << why;
  return k;
}

// The "true" arm, not written in the identified parameterization: the UR5's KDL chain with a
// seeded random rigid offset (+-1 mm per axis, +-0.2 deg per roll/pitch/yaw) before joint 1 and
// after every segment, i.e. every joint origin and tool0 moved, and the point 5 cm out from tool0.
struct PerturbedChain {
  KDL::Chain chain;
  KDL::Frame base;
  std::vector<KDL::Frame> after;  // one per segment

  PerturbedChain(const KDL::Chain& nominal, std::mt19937& rng) : chain(nominal) {
    std::uniform_real_distribution<double> u(-1, 1);
    const double mm = 1e-3, deg = kPi / 180;
    auto offset = [&] {
      const KDL::Vector p(mm * u(rng), mm * u(rng), mm * u(rng));
      const double r = 0.2 * deg * u(rng), pi = 0.2 * deg * u(rng), y = 0.2 * deg * u(rng);
      return KDL::Frame(KDL::Rotation::RPY(r, pi, y), p);
    };
    base = offset();
    for (unsigned s = 0; s < chain.getNrOfSegments(); ++s) after.push_back(offset());
  }

  Eigen::Vector3d position(const Eigen::VectorXd& q) const {
    KDL::Frame T = base;
    int j = 0;
    for (unsigned s = 0; s < chain.getNrOfSegments(); ++s) {
      const KDL::Segment& seg = chain.getSegment(s);
      const bool moving = seg.getJoint().getType() != KDL::Joint::None;
      T = T * seg.pose(moving ? q[j++] : 0.0) * after[s];
    }
    const KDL::Vector p = T * KDL::Vector(0, 0, 0.05);
    return Eigen::Vector3d(p.x(), p.y(), p.z());
  }
};

struct Data {
  Eigen::MatrixXd q, p, p_true;
};

template <class Arm>
Data measure(const Arm& truth, int m, double noise, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-kPi, kPi);
  std::normal_distribution<double> n(0.0, noise);
  Data d{Eigen::MatrixXd(6, m), Eigen::MatrixXd(3, m), Eigen::MatrixXd(3, m)};
  for (int k = 0; k < m; ++k) {
    for (int i = 0; i < 6; ++i) d.q(i, k) = u(rng);
    d.p_true.col(k) = truth.position(d.q.col(k));
    d.p.col(k) = d.p_true.col(k) + Eigen::Vector3d(n(rng), n(rng), n(rng));
  }
  return d;
}

TEST(KinematicParameters, NominalUr5EqualsTheModelsForwardKinematics) {
  const KinematicParameters k = ur5_nominal();
  ChainKinematics kin;
  std::string why;
  ASSERT_EQ(ChainKinematics::configure(*testing::load_ur5(), &kin, &why), Status::kOk);
  std::mt19937 rng(43);
  std::uniform_real_distribution<double> u(-kPi, kPi);
  for (int j = 0; j < 50; ++j) {
    Eigen::VectorXd q(6);
    for (int i = 0; i < 6; ++i) q[i] = u(rng);
    Eigen::Isometry3d T;
    kin.forward(q, T);
    EXPECT_LT((k.position(q) - T * Eigen::Vector3d(0, 0, 0.05)).norm(), 1e-12);
  }
  // UR joints 2, 3, 4 are parallel to their predecessors: beta is identified there only.
  EXPECT_EQ(k.has_beta, (std::vector<bool>{false, false, true, true, false, false}));
}

// A UR5 mounted with an offset before joint 1 (xyz and rpy on shoulder_pan_joint's origin): the
// parameters carry that base, so they reproduce the model's own FK.
TEST(KinematicParameters, FromUrModelCarriesTheBaseTransform) {
  std::ifstream file(testing::ur5_urdf_path());
  std::stringstream text;
  text << file.rdbuf();
  std::string xml = text.str();
  const std::string joint1 = "<child link=\"shoulder_link\"/>\n    <origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>";
  const auto at = xml.find(joint1);
  ASSERT_NE(at, std::string::npos);
  xml.replace(at, joint1.size(),
              "<child link=\"shoulder_link\"/>\n    <origin xyz=\"0.3 -0.2 0.5\" rpy=\"0.4 -0.3 2.5\"/>");
  RobotModel model;
  std::string why;
  ASSERT_EQ(model_from_urdf_string(xml, "", "", &model, &why), Status::kOk) << why;
  const Eigen::Vector3d tool_point(0.01, -0.02, 0.05);
  KinematicParameters k;
  ASSERT_EQ(KinematicParameters::from_ur_model(model, tool_point, &k, &why), Status::kOk) << why;
  ChainKinematics kin;
  ASSERT_EQ(ChainKinematics::configure(model, &kin, &why), Status::kOk);
  const unsigned seed = 61;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-kPi, kPi);
  double worst = 0.0, worst_without_base = 0.0;
  KinematicParameters no_base = k;
  no_base.base_position.setZero();
  no_base.base_rotation.setZero();
  for (int j = 0; j < 50; ++j) {
    Eigen::VectorXd q(6);
    for (int i = 0; i < 6; ++i) q[i] = u(rng);
    Eigen::Isometry3d T;
    kin.forward(q, T);
    worst = std::max(worst, (k.position(q) - T * tool_point).norm());
    worst_without_base = std::max(worst_without_base, (no_base.position(q) - T * tool_point).norm());
  }
  std::printf("seed %u: worst FK deviation %.3g m (%.3g m with the base dropped)\n", seed, worst,
              worst_without_base);
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(worst_without_base, 0.1);  // the offset is real: dropping it is visible
  // A chain that is not UR-shaped is refused with a reason.
  RobotModel planar;
  ASSERT_EQ(model_from_dh(testing::PlanarArm{}.table(), DhConvention::kStandard, &planar, &why), Status::kOk);
  EXPECT_EQ(KinematicParameters::from_ur_model(planar, tool_point, &k, &why), Status::kModelError);
  EXPECT_FALSE(why.empty());
}

TEST(KinematicCalibration, RecoversThePerturbedUr5ToBelowHalfAMillimetre) {
  const unsigned seed = 47;
  std::mt19937 rng(seed);
  const KinematicParameters nominal = ur5_nominal();
  const PerturbedChain truth(testing::load_ur5()->chain(), rng);
  const Data train = measure(truth, 60, 1e-4, rng);
  const Data test = measure(truth, 50, 1e-4, rng);
  CalibrationResult res;
  std::string why;
  ASSERT_EQ(calibrate_kinematics(nominal, train.q, train.p, CalibrationConfig{}, &res, &why),
            Status::kOk) << why;
  double rms_nom, max_nom, rms, max, rms_true, max_true;
  position_residuals(nominal, test.q, test.p, &rms_nom, &max_nom);
  position_residuals(res.parameters, test.q, test.p, &rms, &max);
  position_residuals(res.parameters, test.q, test.p_true, &rms_true, &max_true);
  std::printf("seed %u: %d parameters, rank %d, condition %.1f, O1 %.3g; held-out RMS %.3f mm "
              "(nominal %.3f mm), max vs truth %.3f mm\n", seed, res.num_parameters, res.rank,
              res.condition_number, res.observability_index, rms * 1e3, rms_nom * 1e3, max_true * 1e3);
  EXPECT_GT(rms_nom, 2e-3);  // the perturbation matters: millimetres before calibration
  EXPECT_LT(rms, 0.5e-3);
  EXPECT_LT(max_true, 0.5e-3);
  EXPECT_LT(res.rank, res.num_parameters);  // base/joint-1 and d-chain redundancies exist
  EXPECT_LT(res.condition_number, 1e4);
}

TEST(KinematicCalibration, WithoutBetaTheParallelAxisTiltCannotBeFitted) {
  std::mt19937 rng(53);
  const KinematicParameters nominal = ur5_nominal();
  KinematicParameters truth = nominal;
  truth.beta[2] = 0.3 * kPi / 180;  // joint 3 axis tilted 0.3 deg against joint 2's
  const Data train = measure(truth, 60, 1e-4, rng);
  CalibrationConfig plain;
  plain.identify_beta = false;
  CalibrationResult with_beta, without;
  std::string why;
  ASSERT_EQ(calibrate_kinematics(nominal, train.q, train.p, CalibrationConfig{}, &with_beta, &why),
            Status::kOk);
  ASSERT_EQ(calibrate_kinematics(nominal, train.q, train.p, plain, &without, &why), Status::kOk);
  EXPECT_LT(with_beta.rms_residual, 0.25e-3);
  EXPECT_GT(without.rms_residual, 2 * with_beta.rms_residual);
}

// O1 is a per-pose figure: with twice the poses from the same distribution it stays put (with
// unit-norm columns it fell as 1/sqrt(m), 0.71x here).
TEST(KinematicCalibration, ObservabilityIndexDoesNotDropWhenThePoseCountDoubles) {
  const unsigned seed = 59;
  std::mt19937 rng(seed);
  const KinematicParameters nominal = ur5_nominal();
  const Data few = measure(nominal, 100, 1e-4, rng);
  const Data many = measure(nominal, 200, 1e-4, rng);
  CalibrationResult r_few, r_many;
  std::string why;
  ASSERT_EQ(calibrate_kinematics(nominal, few.q, few.p, CalibrationConfig{}, &r_few, &why), Status::kOk);
  ASSERT_EQ(calibrate_kinematics(nominal, many.q, many.p, CalibrationConfig{}, &r_many, &why), Status::kOk);
  std::printf("seed %u: O1 %.4f mm (100 poses), %.4f mm (200 poses)\n", seed, r_few.observability_index,
              r_many.observability_index);
  EXPECT_EQ(r_few.rank, r_many.rank);
  EXPECT_GT(r_many.observability_index, 0.9 * r_few.observability_index);
  EXPECT_LT(r_many.observability_index, 1.1 * r_few.observability_index);
  // Coarser ranges scale every retained singular value, and so O1, by the same factor.
  CalibrationConfig coarse;
  coarse.length_range = coarse.angle_range = 2e-3;
  CalibrationResult r_coarse;
  ASSERT_EQ(calibrate_kinematics(nominal, few.q, few.p, coarse, &r_coarse, &why), Status::kOk);
  EXPECT_NEAR(r_coarse.observability_index, 2 * r_few.observability_index, 1e-9);
}

TEST(KinematicCalibration, RejectsBadData) {
  const KinematicParameters nominal = ur5_nominal();
  CalibrationResult res;
  std::string why;
  EXPECT_EQ(calibrate_kinematics(nominal, Eigen::MatrixXd::Zero(5, 10), Eigen::MatrixXd::Zero(3, 10),
                                 CalibrationConfig{}, &res, &why),
            Status::kBadSize);
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero(3, 10);
  p(1, 1) = NAN;
  EXPECT_EQ(calibrate_kinematics(nominal, Eigen::MatrixXd::Zero(6, 10), p, CalibrationConfig{}, &res, &why),
            Status::kNonFiniteMeasurement);
  CalibrationConfig no_range;
  no_range.angle_range = 0.0;
  EXPECT_EQ(validate(no_range, &why), Status::kInvalidConfig);
}

}  // namespace
}  // namespace kiloloop
