// Friction compensation of the joint torque controllers: the exact feed-forward on the reference
// velocity, off (bit-identical) at zero, validated, allocation-free.
#include <cmath>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"
#include "joint_inputs.hpp"
#include "kiloloop/control/computed_torque.hpp"
#include "kiloloop/control/joint_pd_gravity.hpp"
#include "test_models.hpp"

namespace kiloloop {
namespace {

template <class Controller, class Config>
Controller make(RobotModelPtr model, const Config& config) {
  Controller c;
  std::string why;
  EXPECT_EQ(Controller::configure(config, model, &c, &why), Status::kOk) << why;
  return c;
}

JointControlInput input(int n, unsigned seed) {
  std::mt19937 rng(seed);
  return testing::random_joint_input(rng, n);
}

template <class Controller, class Config>
void check_feedforward() {
  auto model = testing::load_ur5();
  const int n = model->nq();
  Config plain;
  plain.kp = Eigen::VectorXd::Constant(1, 100.0);  // stays below the effort limits
  plain.kd = Eigen::VectorXd::Constant(1, 10.0);
  Config with = plain;
  with.friction.viscous = Eigen::VectorXd::LinSpaced(n, 0.5, 3.0);
  with.friction.coulomb = Eigen::VectorXd::Constant(1, 0.8);
  with.friction.smoothing_speed = 0.05;
  auto a = make<Controller>(model, plain);
  auto b = make<Controller>(model, with);
  for (unsigned seed = 0; seed < 50; ++seed) {
    const JointControlInput in = input(n, seed);
    JointControlOutput oa = a.make_output(), ob = b.make_output();
    ASSERT_EQ(a.step(in, oa), Status::kOk);
    ASSERT_EQ(b.step(in, ob), Status::kOk);
    for (int i = 0; i < n; ++i) {
      const double expected = with.friction.viscous[i] * in.qd_ref[i] +
                              0.8 * std::tanh(in.qd_ref[i] / 0.05);
      EXPECT_NEAR(ob.tau[i] - oa.tau[i], expected, 1e-12) << "seed " << seed << " joint " << i;
    }
  }
}

TEST(JointFriction, ComputedTorqueAddsViscousAndSmoothedCoulombOnTheReferenceVelocity) {
  check_feedforward<ComputedTorqueController, ComputedTorqueConfig>();
}

TEST(JointFriction, PdGravityAddsViscousAndSmoothedCoulombOnTheReferenceVelocity) {
  check_feedforward<JointPdGravityController, JointPdGravityConfig>();
}

TEST(JointFriction, ZeroFrictionIsBitIdenticalToNone) {
  auto model = testing::load_ur5();
  ComputedTorqueConfig zero;
  zero.friction.smoothing_speed = 1.0;  // irrelevant when both coefficients are 0
  auto a = make<ComputedTorqueController>(model, ComputedTorqueConfig{});
  auto b = make<ComputedTorqueController>(model, zero);
  const JointControlInput in = input(model->nq(), 7);
  JointControlOutput oa = a.make_output(), ob = b.make_output();
  a.step(in, oa);
  b.step(in, ob);
  EXPECT_EQ(0, std::memcmp(oa.tau.data(), ob.tau.data(), sizeof(double) * oa.tau.size()));
}

TEST(JointFriction, RejectsBadSettings) {
  auto model = testing::load_ur5();
  std::string why;
  ComputedTorqueController c;
  ComputedTorqueConfig bad;
  bad.friction.viscous = Eigen::VectorXd::Constant(2, 1.0);  // neither 1 nor nq
  EXPECT_EQ(ComputedTorqueController::configure(bad, model, &c, &why), Status::kInvalidConfig);
  EXPECT_NE(why.find("friction.viscous"), std::string::npos) << why;
  bad = ComputedTorqueConfig{};
  bad.friction.coulomb = Eigen::VectorXd::Constant(1, -1.0);
  EXPECT_EQ(ComputedTorqueController::configure(bad, model, &c, &why), Status::kInvalidConfig);
  bad = ComputedTorqueConfig{};
  bad.friction.smoothing_speed = 0.0;
  EXPECT_EQ(ComputedTorqueController::configure(bad, model, &c, &why), Status::kInvalidConfig);
}

TEST(JointFriction, StepsStayAllocationFree) {
  auto model = testing::load_ur5();
  ComputedTorqueConfig config;
  config.friction.viscous = Eigen::VectorXd::Constant(1, 2.0);
  config.friction.coulomb = Eigen::VectorXd::Constant(1, 1.0);
  auto c = make<ComputedTorqueController>(model, config);
  const JointControlInput in = input(model->nq(), 3);
  JointControlOutput out = c.make_output();
  testing::AllocationScope scope;
  for (int k = 0; k < 1000; ++k) c.step(in, out);
  EXPECT_EQ(scope.count(), 0u);
}

}  // namespace
}  // namespace kiloloop
