#include "kiloloop/quadruped/free_leg_inertia.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/jntspaceinertiamatrix.hpp>

namespace kiloloop {
namespace {

// Inertia of everything hanging off `el` outside the chain (rotors, covers: rigid with it,
// joints off the chain taken at 0), in el's frame.
KDL::RigidBodyInertia off_chain(KDL::SegmentMap::const_iterator el, const std::string& next_on_chain) {
  KDL::RigidBodyInertia sum = KDL::RigidBodyInertia::Zero();
  for (const auto& child : GetTreeElementChildren(el->second)) {
    if (child->first == next_on_chain) continue;
    const KDL::Segment& seg = GetTreeElementSegment(child->second);
    sum = sum + seg.pose(0.0) * (seg.getInertia() + off_chain(child, ""));
  }
  return sum;
}

}  // namespace

KDL::Chain leg_chain(const RobotModel& model, const std::string& trunk, const std::string& foot) {
  KDL::Chain chain, out;
  model.tree().getChain(trunk, foot, chain);
  const KDL::SegmentMap& map = model.tree().getSegments();
  for (unsigned s = 0; s < chain.getNrOfSegments(); ++s) {
    const KDL::Segment& seg = chain.getSegment(s);
    const std::string next = s + 1 < chain.getNrOfSegments() ? chain.getSegment(s + 1).getName() : "";
    const KDL::RigidBodyInertia I = seg.getInertia() + off_chain(map.find(seg.getName()), next);
    out.addSegment(KDL::Segment(seg.getName(), seg.getJoint(), seg.getFrameToTip(), I));
  }
  return out;
}

Eigen::Matrix3d FreeLegInertia::rotational(const std::array<bool, 4>& free) const noexcept {
  Matrix6d S = composite;
  for (int leg = 0; leg < 4; ++leg)
    if (free[leg]) S -= coupling[leg];
  const Eigen::Matrix3d lin = S.topLeftCorner<3, 3>();
  return S.bottomRightCorner<3, 3>() -
         S.bottomLeftCorner<3, 3>() * lin.inverse() * S.topRightCorner<3, 3>();
}

FreeLegInertia free_leg_inertia(const RobotModel& model, const std::string& trunk,
                                const std::array<std::string, 4>& feet,
                                const Eigen::Matrix<double, 12, 1>& q, double mass,
                                const Eigen::Vector3d& com, const Eigen::Matrix3d& composite) {
  FreeLegInertia out;
  out.composite.setZero();  // [linear; angular] momentum about the CoM, trunk frame
  out.composite.topLeftCorner<3, 3>() = mass * Eigen::Matrix3d::Identity();
  out.composite.bottomRightCorner<3, 3>() = composite;
  for (int leg = 0; leg < 4; ++leg) {
    const KDL::Chain chain = leg_chain(model, trunk, feet[leg]);
    const unsigned n = chain.getNrOfJoints();
    KDL::JntArray qj(n);
    for (unsigned k = 0; k < n && k < 3; ++k) qj(k) = q[3 * leg + k];
    KDL::ChainFkSolverPos_recursive fk(chain);
    KDL::ChainJntToJacSolver jac_solver(chain);
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(6, n);  // momentum per unit joint velocity
    for (unsigned s = 0; s < chain.getNrOfSegments(); ++s) {
      KDL::RigidBodyInertia I = chain.getSegment(s).getInertia();  // RefPoint is not const
      if (I.getMass() <= 0) continue;
      KDL::Frame F;
      fk.JntToCart(qj, F, static_cast<int>(s) + 1);
      KDL::Jacobian J(n);
      J.data.setZero();
      jac_solver.JntToJac(qj, J, static_cast<int>(s) + 1);
      const KDL::Vector cog = F.M * I.getCOG();  // from the segment origin, trunk axes
      J.changeRefPoint(cog);
      const KDL::Vector c_link = F.p + cog;
      const Eigen::Vector3d r = Eigen::Vector3d(c_link.x(), c_link.y(), c_link.z()) - com;
      const KDL::RotationalInertia Ic_local = I.RefPoint(I.getCOG()).getRotationalInertia();
      const Eigen::Matrix3d R = Eigen::Map<const Eigen::Matrix3d>(F.M.data).transpose();  // KDL row-major
      const Eigen::Matrix3d Ic = R * Eigen::Map<const Eigen::Matrix3d>(Ic_local.data) * R.transpose();
      const Eigen::MatrixXd Jv = J.data.topRows(3), Jw = J.data.bottomRows(3);
      const double m = I.getMass();
      A.topRows(3) += m * Jv;
      for (unsigned k = 0; k < n; ++k)
        A.block(3, k, 3, 1) += Ic * Jw.col(k) + m * r.cross(Eigen::Vector3d(Jv.col(k)));
    }
    KDL::ChainDynParam dyn(chain, KDL::Vector::Zero());
    KDL::JntSpaceInertiaMatrix H(n);
    dyn.JntToMass(qj, H);
    out.coupling[leg] = A * H.data.inverse() * A.transpose();
    if (n == 3) {
      out.momentum[leg] = A;
      out.joint_inertia_inverse[leg] = H.data.inverse();
    }
  }
  return out;
}

}  // namespace kiloloop
