#pragma once
// A leg's joint-space inertia H(q) (3x3, [kg m^2]) at any pose, for the swing joints' predictor:
// the composite-rigid-body algorithm over the trunk -> foot chain (KDL's ChainDynParam::JntToMass,
// here without allocation so step() can call it). Folding a leg for its swing lowers the hip's
// inertia about 2x on Go1 (0.023 -> 0.012 kg m^2 from standing to the swing's apex), so the
// standing pose's H mispredicts the joints' motion over a long delay.
#include <array>

#include <Eigen/Core>
#include <kdl/chain.hpp>

namespace kiloloop {

class LegJointInertia {
 public:
  // The segments a leg chain may have (joints, fixed links, rotors folded in by leg_chain).
  static constexpr int kMaxSegments = 16;
  LegJointInertia() = default;
  // Configure-time: the chain trunk -> foot with 3 moving joints (false: any other).
  bool configure(const KDL::Chain& chain);
  // [kg m^2] H at the joint angles q (abduction, hip pitch, knee). Allocation-free.
  Eigen::Matrix3d at(const Eigen::Vector3d& q) const noexcept;

 private:
  KDL::Chain chain_;
  int segments_ = 0;
};

}  // namespace kiloloop
