#pragma once
// Stance-force distribution: the ground reaction forces f_i (world frame, one 3-vector per foot)
// that best produce a desired trunk wrench w = [F; tau] about the centre of mass:
//   minimize   |A f - w|^2_S + alpha |f|^2 + beta |f - f_prev|^2
//   subject to friction pyramid |f.t1|, |f.t2| <= mu f.n   (n: ground normal, t1, t2: tangents)
//              fz_min <= f.n <= fz_min + load_i (fz_max - fz_min)   (stance feet; load_i in
//                                                            [0, 1] hands the weight over smoothly
//                                                            at touch-down and lift-off)
//              f_i = 0                                      (feet not in stance: lb = ub = 0,
//                                                            eliminated by the solver)
// with A = [I ... I; [r_1]x ... [r_4]x], r_i the foot position relative to the CoM. When no
// constraint binds at the unconstrained optimum (most ticks of a trot) that optimum is the answer,
// found in closed form through a 6x6 system; otherwise kiloloop's dense QP solves it (3 variables
// per stance foot). Allocation-free after configure.
#include <array>
#include <string>

#include <Eigen/Core>

#include "kiloloop/qp/dense_qp.hpp"
#include "kiloloop/status.hpp"

namespace kiloloop {

struct StanceForceConfig {
  // S diagonal. On two diagonal feet the moment about the support line can only come from a
  // horizontal force (the CoM sits above the line): moments weigh more than the forces so the
  // QP buys the roll moment with a little sideways sway (1-2 mm) instead of letting the trunk
  // roll (measured trot roll RMS on the 17.6 kg model: weight 10 -> 1.4 deg, 100 -> 0.15 deg).
  // The quadruped controller derives the moment weights from the robot's mass, inertia and CoM
  // height (QuadrupedConfig::force); 100 is this class's standalone default.
  Eigen::Matrix<double, 6, 1> wrench_weight =
      (Eigen::Matrix<double, 6, 1>() << 1.0, 1.0, 1.0, 100.0, 100.0, 100.0).finished();
  double regularization = 1e-4;  // alpha [1/N^2 relative to S]
  double smoothing = 1e-3;       // beta: against change from the previous tick
  double mu = 0.8;               // friction coefficient used by the pyramid
  double fz_min = 5.0;           // [N] minimum normal force of a stance foot
  double fz_max = 300.0;         // [N]
  int max_iterations = 100;      // active-set changes per solve before it reports not converged
};

// mu > 0, 0 <= fz_min < fz_max, non-negative weights, max_iterations >= 1; the reason in *why.
Status validate(const StanceForceConfig& config, std::string* why);

class StanceForceQp {
 public:
  static constexpr int kLegs = 4;
  static Status configure(const StanceForceConfig& config, StanceForceQp* out, std::string* why);
  // feet: positions relative to the CoM (world axes); stance: which feet may push; load: the
  // fraction of the normal-force range each stance foot may use (1 = up to fz_max).
  // On success writes f (12) and returns kOk; on QP failure keeps the previous forces (also in f)
  // and returns kSolverFailed.
  Status solve(const Eigen::Matrix<double, 6, 1>& wrench, const std::array<Eigen::Vector3d, kLegs>& feet,
               const std::array<bool, kLegs>& stance, const std::array<double, kLegs>& load,
               const Eigen::Vector3d& normal, Eigen::Matrix<double, 12, 1>& f) noexcept;
  const qp::QpResult& last_result() const { return result_; }
  // Whether the last solve's answer was the closed-form unconstrained optimum (no QP solve).
  bool last_closed_form() const { return closed_form_; }

 private:
  void hessian_of_wrench(const int* legs, int count) noexcept;  // H_ = A_^T S A_ (stance_force.cpp)
  // The unconstrained optimum of the stance legs' forces in f, if it meets every constraint row
  // (rows: the friction pyramid's four, nrm: the unit normal); false leaves f alone.
  bool unconstrained_optimum(const Eigen::Matrix<double, 6, 1>& wrench,
                             const std::array<Eigen::Vector3d, kLegs>& feet, const int* legs, int count,
                             const Eigen::Vector3d (&rows)[4], const Eigen::Vector3d& nrm,
                             const std::array<double, kLegs>& load, Eigen::Matrix<double, 12, 1>& f) noexcept;
  double normal_force_cap(double load) const noexcept;  // [N], fz_max scaled by the load share

  StanceForceConfig cfg_;
  qp::DenseQpSolver solver_;
  qp::QpResult result_;
  bool closed_form_ = false;
  Eigen::Matrix<double, 6, 1> sqrt_weight_;  // S^1/2's diagonal
  Eigen::Matrix<double, 6, 12> A_;
  Eigen::Matrix<double, 12, 12> H_;
  Eigen::Matrix<double, 12, 1> g_, gc_, f_prev_, xc_;  // gc_, xc_: the stance legs' (3 a + c)
  Eigen::MatrixXd no_rows_, C_;  // (0 x 12) and (24 x 12), preallocated; leading blocks used
  Eigen::VectorXd d_, none_;
};

}  // namespace kiloloop
