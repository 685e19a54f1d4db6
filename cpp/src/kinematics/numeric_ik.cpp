#include "kiloloop/kinematics/numeric_ik.hpp"

#include <cmath>

namespace kiloloop {
namespace {

constexpr int kPrimes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53,
                           59, 61, 67, 71, 73, 79, 83, 89, 97, 101, 103, 107, 109, 113, 127, 131};
constexpr int kNumPrimes = sizeof(kPrimes) / sizeof(kPrimes[0]);

// Radical inverse of `index` in `base`: the Halton sequence, in [0, 1).
double halton(int index, int base) {
  double f = 1.0, r = 0.0;
  while (index > 0) {
    f /= base;
    r += f * (index % base);
    index /= base;
  }
  return r;
}

constexpr double kMuMin = 1e-8, kMuMax = 1e8;

}  // namespace

Status validate(const NumericIkConfig& c, std::string* why) {
  auto fail = [why](const char* msg) {
    if (why) *why = msg;
    return Status::kInvalidConfig;
  };
  if (c.max_iterations < 1) return fail("max_iterations must be >= 1");
  if (c.restart_after < 0) return fail("restart_after must be >= 0");
  if (!(c.position_tolerance > 0.0) || !(c.orientation_tolerance > 0.0) ||
      !std::isfinite(c.position_tolerance) || !std::isfinite(c.orientation_tolerance))
    return fail("position_tolerance and orientation_tolerance must be finite and > 0");
  if (!c.weights.allFinite() || (c.weights.array() < 0.0).any() || c.weights.maxCoeff() <= 0.0)
    return fail("weights must be finite, >= 0, and not all 0");
  if (!(c.lambda_floor >= 0.0) || !std::isfinite(c.lambda_floor))
    return fail("lambda_floor must be finite and >= 0");
  if (!(c.mu_initial > 0.0) || !std::isfinite(c.mu_initial)) return fail("mu_initial must be > 0");
  if (!(c.unbounded_range > 0.0) || !std::isfinite(c.unbounded_range))
    return fail("unbounded_range must be finite and > 0");
  return Status::kOk;
}

Status NumericIk::configure(const NumericIkConfig& config, const RobotModel& model, NumericIk* out,
                            std::string* why) {
  Status s = validate(config, why);
  if (failed(s)) return s;
  NumericIk ik;
  s = ChainKinematics::configure(model, &ik.kin_, why);
  if (failed(s)) return s;
  const int n = ik.kin_.nq();
  ik.config_ = config;
  ik.lower_ = model.lower();
  ik.upper_ = model.upper();
  if (!config.joint_limits) {
    ik.lower_.setConstant(-std::numeric_limits<double>::infinity());
    ik.upper_.setConstant(std::numeric_limits<double>::infinity());
  }
  // Restart points cover the finite range, or +-unbounded_range where a limit is infinite.
  ik.lo_restart_ = ik.lower_.cwiseMax(-config.unbounded_range);
  ik.hi_restart_ = ik.upper_.cwiseMin(config.unbounded_range);
  for (int i = 0; i < n; ++i) {
    if (ik.lo_restart_[i] > ik.hi_restart_[i]) ik.lo_restart_[i] = ik.hi_restart_[i] = ik.lower_[i];
  }
  ik.q_ = ik.q_try_ = ik.dq_ = ik.g_ = ik.best_ = Eigen::VectorXd::Zero(n);
  ik.J_ = ik.J_try_ = ik.WJ_ = Eigen::MatrixXd::Zero(6, n);
  ik.A_ = ik.A_act_ = Eigen::MatrixXd::Zero(n, n);
  ik.g_act_ = ik.active_ = Eigen::VectorXd::Zero(n);
  // Sized by computing once (not by assigning LDLT(n): that temporary never computed, and moving
  // it reads its unset status field, UBSan: invalid value for ComputationInfo).
  ik.ldlt_.compute(Eigen::MatrixXd::Identity(n, n));
  *out = std::move(ik);
  return Status::kOk;
}

void NumericIk::clamp(Eigen::Ref<Eigen::VectorXd> q) const noexcept {
  q = q.cwiseMax(lower_).cwiseMin(upper_);
}

void NumericIk::restart_point(int index, Eigen::Ref<Eigen::VectorXd> q) const noexcept {
  for (int i = 0; i < q.size(); ++i) {
    // Past the table of primes the coordinates reuse bases: still deterministic, less uniform.
    const double h = halton(index, kPrimes[i % kNumPrimes]);
    q[i] = lo_restart_[i] + h * (hi_restart_[i] - lo_restart_[i]);
  }
}

double NumericIk::evaluate(const Eigen::Isometry3d& target, const Eigen::Isometry3d& T, Vector6d& e,
                           bool* converged, double* pos_err, double* rot_err) const noexcept {
  e = pose_error(target, T);
  const Vector6d& w = config_.weights;
  // Tolerances apply to the constrained (w > 0) components only.
  const Vector6d mask = (w.array() > 0.0).cast<double>();
  const Vector6d m = e.cwiseProduct(mask);
  *pos_err = m.head<3>().norm();
  *rot_err = m.tail<3>().norm();
  *converged = *pos_err <= config_.position_tolerance && *rot_err <= config_.orientation_tolerance;
  return e.dot(w.cwiseProduct(e));
}

bool NumericIk::limited_step() noexcept {
  // Active set on the joint limits: a joint whose step would cross its limit is fixed at the
  // limit and the others re-solve the damped system with that motion given. Clamping the full
  // step instead is not a descent direction and stalls at the limits (measured: 40 % vs 90 %
  // single-start success on the 7-DoF arm).
  const int n = nq();
  active_.setZero();
  for (int pass = 0; pass <= n; ++pass) {
    A_act_ = A_;
    g_act_ = g_;
    for (int i = 0; i < n; ++i) {
      if (!active_[i]) continue;
      const double delta = dq_[i];  // fixed motion to the limit, from the previous pass
      g_act_ -= A_.col(i) * delta;
      A_act_.row(i).setZero();
      A_act_.col(i).setZero();
      A_act_(i, i) = 1.0;
      g_act_[i] = delta;
    }
    ldlt_.compute(A_act_);
    dq_ = ldlt_.solve(g_act_);
    if (!dq_.allFinite()) return false;
    bool added = false;
    for (int i = 0; i < n; ++i) {
      if (active_[i]) continue;
      const double target = q_[i] + dq_[i];
      if (target < lower_[i] || target > upper_[i]) {
        active_[i] = 1.0;
        added = true;
      }
    }
    if (!added) return true;
    // Fix the violators at their limits for the next pass (dq_ holds the motion to the limit).
    for (int i = 0; i < n; ++i)
      if (active_[i]) dq_[i] = std::min(std::max(q_[i] + dq_[i], lower_[i]), upper_[i]) - q_[i];
  }
  return true;
}

Status NumericIk::solve(const Eigen::Isometry3d& target, const Eigen::Ref<const Eigen::VectorXd>& seed,
                        Eigen::Ref<Eigen::VectorXd> q) noexcept {
  return run(target, seed, config_.max_iterations, config_.restart_after > 0, q);
}

Status NumericIk::refine(const Eigen::Isometry3d& target, const Eigen::Ref<const Eigen::VectorXd>& guess,
                         int iterations, Eigen::Ref<Eigen::VectorXd> q) noexcept {
  return run(target, guess, iterations < 0 ? 0 : iterations, false, q);
}

Status NumericIk::run(const Eigen::Isometry3d& target, const Eigen::Ref<const Eigen::VectorXd>& seed,
                      int budget, bool restarts, Eigen::Ref<Eigen::VectorXd> q) noexcept {
  report_ = IkReport{};
  const int n = nq();
  if (n == 0) return Status::kNotConfigured;
  if (seed.size() != n || q.size() != n) return Status::kBadSize;
  if (!seed.allFinite()) {
    q = lower_.cwiseMax(Eigen::VectorXd::Zero(n)).cwiseMin(upper_);
    return Status::kNonFiniteMeasurement;
  }
  q_ = seed;
  clamp(q_);
  if (!target.matrix().allFinite()) {
    q = q_;
    return Status::kNonFiniteReference;
  }
  const Vector6d& w = config_.weights;
  Eigen::Isometry3d T;
  Vector6d e, e_try;
  bool conv = false;
  double pos = 0.0, rot = 0.0;
  kin_.forward_jacobian(q_, T, J_);
  double E = evaluate(target, T, e, &conv, &pos, &rot);
  double best_E = E, best_pos = pos, best_rot = rot;
  best_ = q_;
  double mu = config_.mu_initial;
  int since_restart = 0, restart_index = 1;
  int it = 0;
  while (!conv && it < budget) {
    if (restarts && since_restart >= config_.restart_after) {
      restart_point(restart_index++, q_);
      ++report_.restarts;
      since_restart = 0;
      mu = config_.mu_initial;
      kin_.forward_jacobian(q_, T, J_);
      E = evaluate(target, T, e, &conv, &pos, &rot);
      if (E < best_E) best_E = E, best_pos = pos, best_rot = rot, best_ = q_;
      if (conv) break;
    }
    ++it;
    ++since_restart;
    // Damped normal equations.
    WJ_.noalias() = w.asDiagonal() * J_;
    A_.noalias() = J_.transpose() * WJ_;
    A_.diagonal().array() += mu * (E + config_.lambda_floor);
    g_.noalias() = WJ_.transpose() * e;
    if (!limited_step()) {
      mu = std::min(mu * 4.0, kMuMax);
      continue;
    }
    q_try_ = q_ + dq_;
    clamp(q_try_);
    kin_.forward_jacobian(q_try_, T, J_try_);
    bool conv_try = false;
    double pos_try = 0.0, rot_try = 0.0;
    const double E_try = evaluate(target, T, e_try, &conv_try, &pos_try, &rot_try);
    if (E_try < E) {
      q_.swap(q_try_);
      J_.swap(J_try_);
      e = e_try;
      E = E_try, conv = conv_try, pos = pos_try, rot = rot_try;
      mu = std::max(mu * 0.5, kMuMin);
      if (E < best_E) best_E = E, best_pos = pos, best_rot = rot, best_ = q_;
    } else {
      mu = std::min(mu * 4.0, kMuMax);
    }
  }
  report_.iterations = it;
  if (conv) {
    q = q_;
    report_.position_error = pos;
    report_.orientation_error = rot;
    return Status::kOk;
  }
  q = best_;
  report_.position_error = best_pos;
  report_.orientation_error = best_rot;
  return Status::kIterationLimit;
}

}  // namespace kiloloop
