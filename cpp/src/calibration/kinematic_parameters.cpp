#include "kiloloop/calibration/kinematic_parameters.hpp"

#include <cmath>

#include <Eigen/Geometry>

#include "kiloloop/kinematics/ur_analytic_ik.hpp"

namespace kiloloop {

Eigen::VectorXd KinematicParameters::pack() const {
  Eigen::VectorXd x(size());
  x << base_position, base_rotation, alpha, a, beta, theta, d, tool;
  return x;
}

bool KinematicParameters::unpack(const Eigen::VectorXd& x) {
  const int n = nq();
  if (x.size() != size()) return false;
  base_position = x.segment<3>(0);
  base_rotation = x.segment<3>(3);
  alpha = x.segment(6, n);
  a = x.segment(6 + n, n);
  beta = x.segment(6 + 2 * n, n);
  theta = x.segment(6 + 3 * n, n);
  d = x.segment(6 + 4 * n, n);
  tool = x.segment<3>(6 + 5 * n);
  return true;
}

Eigen::Vector3d KinematicParameters::position(const Eigen::VectorXd& q) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = base_position;
  const double angle = base_rotation.norm();
  if (angle > 0.0) T.linear() = Eigen::AngleAxisd(angle, base_rotation / angle).toRotationMatrix();
  for (int i = 0; i < nq(); ++i) {
    T.rotate(Eigen::AngleAxisd(alpha[i], Eigen::Vector3d::UnitX()));
    T.translate(Eigen::Vector3d(a[i], 0.0, 0.0));
    T.rotate(Eigen::AngleAxisd(beta[i], Eigen::Vector3d::UnitY()));
    T.rotate(Eigen::AngleAxisd(theta[i] + q[i], Eigen::Vector3d::UnitZ()));
    T.translate(Eigen::Vector3d(0.0, 0.0, d[i]));
  }
  return T * tool;
}

Status KinematicParameters::from_dh(const std::vector<DhLink>& links, DhConvention convention,
                                    const Eigen::Vector3d& tool_point, KinematicParameters* out,
                                    std::string* why) {
  const int n = static_cast<int>(links.size());
  if (n == 0) {
    if (why) *why = "DH table is empty";
    return Status::kModelError;
  }
  KinematicParameters k;
  k.alpha = k.a = k.beta = k.theta = k.d = Eigen::VectorXd::Zero(n);
  k.has_beta.assign(n, false);
  for (int i = 0; i < n; ++i) {
    if (links[i].prismatic) {
      if (why) *why = "kinematic calibration supports revolute joints only";
      return Status::kModelError;
    }
    k.theta[i] = links[i].theta;
    k.d[i] = links[i].d;
  }
  Eigen::Isometry3d tool_frame = Eigen::Isometry3d::Identity();
  if (convention == DhConvention::kModified) {
    for (int i = 0; i < n; ++i) k.alpha[i] = links[i].alpha, k.a[i] = links[i].a;
  } else {
    // prod Rz Tz Tx Rx = Rz Tz . [Tx(a_1) Rx(alpha_1) Rz Tz] . ... . Tx(a_n) Rx(alpha_n): the
    // standard row i's (a, alpha) become modified row i+1's; the last pair goes to the tool.
    for (int i = 1; i < n; ++i) k.alpha[i] = links[i - 1].alpha, k.a[i] = links[i - 1].a;
    tool_frame.translate(Eigen::Vector3d(links[n - 1].a, 0, 0));
    tool_frame.rotate(Eigen::AngleAxisd(links[n - 1].alpha, Eigen::Vector3d::UnitX()));
  }
  k.tool = tool_frame * tool_point;
  // Parallel consecutive axes: alpha_i = 0 or pi (mod 2 pi) in the modified convention.
  for (int i = 1; i < n; ++i) k.has_beta[i] = std::abs(std::sin(k.alpha[i])) < 1e-9;
  *out = k;
  return Status::kOk;
}

Status KinematicParameters::from_ur_model(const RobotModel& model, const Eigen::Vector3d& tool_point,
                                          KinematicParameters* out, std::string* why) {
  UrAnalyticIk ik;
  Status s = UrAnalyticIk::from_model(model, &ik, why);
  if (failed(s)) return s;
  // The calibration form has DH angles = joint positions and the tip at DH frame 6: a UR model
  // whose joints are mirrored or offset, or whose tip frame differs from DH frame 6 (real UR
  // URDFs' tool0), would be calibrated silently wrong, so it is refused.
  const double kExact = 1e-12;
  if ((ik.joint_sign().array() != 1.0).any() || ik.joint_offset().cwiseAbs().maxCoeff() > kExact ||
      !ik.tool().isApprox(Eigen::Isometry3d::Identity(), kExact)) {
    if (why)
      *why = "calibration: this UR model's joints are mirrored/offset or its tip is not DH frame 6 "
             "(only models in kiloloop's UR layout are supported by from_ur_model)";
    return Status::kModelError;
  }
  KinematicParameters k;
  s = from_dh(ik.parameters().table(), DhConvention::kStandard, tool_point, &k, why);
  if (failed(s)) return s;
  // The DH product starts at frame 0; a mounting offset before joint 1 is part of the geometry.
  const Eigen::AngleAxisd base_rotation(ik.base().linear());
  k.base_position = ik.base().translation();
  k.base_rotation = base_rotation.angle() * base_rotation.axis();
  *out = k;
  return Status::kOk;
}

}  // namespace kiloloop
