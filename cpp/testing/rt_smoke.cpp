// Built with -fno-exceptions -fno-rtti against kiloloop_core_rt: the firmware flags link and run.
// A two-link DH arm, one computed-torque step and one QP solve; exit 0 when both work.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "kiloloop/control/computed_torque.hpp"
#include "kiloloop/model/dh.hpp"
#include "kiloloop/qp/dense_qp.hpp"

int main() {
  using namespace kiloloop;
  std::vector<DhLink> links(2);
  for (DhLink& l : links) {
    l.a = 0.5;
    l.mass = 1.0;
    l.limit.effort = 100.0;  // [N m]
  }
  auto model = std::make_shared<RobotModel>();
  std::string why;
  if (failed(model_from_dh(links, DhConvention::kStandard, model.get(), &why))) {
    std::printf("rt_smoke: model: %s\n", why.c_str());
    return 1;
  }
  ComputedTorqueController ctrl;
  if (failed(ComputedTorqueController::configure(ComputedTorqueConfig{}, model, &ctrl, &why))) {
    std::printf("rt_smoke: configure: %s\n", why.c_str());
    return 1;
  }
  JointControlInput in = ctrl.make_input();
  JointControlOutput out = ctrl.make_output();
  in.q_ref.setConstant(0.1);
  const Status s = ctrl.step(in, out);

  qp::DenseQpSolver solver;
  if (failed(qp::DenseQpSolver::configure(2, 0, 1, qp::QpSettings{}, &solver, &why))) return 1;
  const Eigen::Matrix2d H = Eigen::Matrix2d::Identity();
  const Eigen::Vector2d g(-1.0, -1.0);
  const Eigen::MatrixXd C = Eigen::MatrixXd::Ones(1, 2), A(0, 2);
  const Eigen::VectorXd d = Eigen::VectorXd::Ones(1), none;
  Eigen::VectorXd x(2);
  const qp::QpResult r = solver.solve(H, g, A, none, C, d, none, none, x);

  std::printf("rt_smoke: step %s, tau = [%g, %g]; qp %s, x = [%g, %g]\n", to_string(s),
              out.tau[0], out.tau[1], qp::to_string(r.status), x[0], x[1]);
  return ok(s) && out.tau.allFinite() && r.status == qp::QpStatus::kOptimal ? 0 : 1;
}
