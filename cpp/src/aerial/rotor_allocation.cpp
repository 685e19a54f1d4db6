#include "kiloloop/aerial/rotor_allocation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>

namespace kiloloop {

namespace {

// A 1-or-n vector broadcast to n.
Eigen::VectorXd per_rotor(const Eigen::VectorXd& v, int n) {
  return v.size() == 1 ? Eigen::VectorXd::Constant(n, v[0]) : v;
}

// Relative singular-value threshold below which a wrench direction counts as unreachable.
constexpr double kRankTolerance = 1e-9;

}  // namespace

Status validate(const RotorAllocationConfig& c, std::string* why) {
  auto fail = [why](const std::string& msg) {
    if (why) *why = "RotorAllocationConfig: " + msg;
    return Status::kInvalidConfig;
  };
  const int n = static_cast<int>(c.positions.cols());
  if (n < 4) return fail("needs at least 4 rotors, got " + std::to_string(n));
  if (!c.positions.allFinite()) return fail("positions must be finite");
  if (c.axes.cols() != 0) {
    if (c.axes.cols() != n) return fail("axes must have one column per rotor (or none: +z)");
    if (!c.axes.allFinite() || (c.axes.colwise().norm().array() < 1e-6).any())
      return fail("axes must be finite non-zero directions");
  }
  if (c.spin.size() != n) return fail("spin must have one entry per rotor");
  for (int i = 0; i < n; ++i)
    if (std::abs(c.spin[i]) != 1.0) return fail("spin must be +1 or -1 per rotor");
  for (const auto* v : {&c.torque_coefficient, &c.thrust_max})
    if (v->size() != 1 && v->size() != n)
      return fail("torque_coefficient/thrust_max must have 1 or n = " + std::to_string(n) +
                  " entries");
  if (!c.torque_coefficient.allFinite() || (c.torque_coefficient.array() < 0).any())
    return fail("torque_coefficient must be >= 0");
  if (!(std::isfinite(c.thrust_min) && c.thrust_min >= 0)) return fail("thrust_min must be >= 0");
  if (!c.thrust_max.allFinite() || (c.thrust_max.array() <= c.thrust_min).any())
    return fail("thrust_max must exceed thrust_min");
  if (!(std::isfinite(c.time_constant) && c.time_constant >= 0))
    return fail("time_constant must be >= 0");
  if (!(std::isfinite(c.dt) && c.dt > 0)) return fail("dt must be > 0");
  return Status::kOk;
}

Status RotorAllocation::configure(const RotorAllocationConfig& config, RotorAllocation* out,
                                  std::string* why) {
  const Status s = validate(config, why);
  if (failed(s)) return s;
  RotorAllocation r;
  r.cfg_ = config;
  const int n = static_cast<int>(config.positions.cols());
  r.n_ = n;
  const Eigen::VectorXd c = per_rotor(config.torque_coefficient, n);
  r.hi_ = per_rotor(config.thrust_max, n);
  r.B_.resize(6, n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d a = config.axes.cols() ? Eigen::Vector3d(config.axes.col(i).normalized())
                                                 : Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d p = config.positions.col(i);
    r.B_.col(i) << a, p.cross(a) - config.spin[i] * c[i] * a;
  }
  r.A_ = r.B_.bottomRows<4>();  // [F_z; tau]

  // The four commanded rows must all be reachable: name the first that is not.
  static const char* kNames[4] = {"collective thrust", "roll torque", "pitch torque",
                                  "yaw torque"};
  Eigen::JacobiSVD<Eigen::MatrixXd> svd4(r.A_, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const double smax = svd4.singularValues()[0];
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector4d e = Eigen::Vector4d::Unit(k);
    svd4.setThreshold(kRankTolerance);
    const Eigen::VectorXd f = svd4.solve(e);
    if (!(smax > 0) || (r.A_ * f - e).norm() > 1e-6) {
      if (why)
        *why = std::string("RotorAllocationConfig: the rotor layout has no ") + kNames[k] +
               " authority (e.g. coplanar rotors without drag torque cannot yaw)";
      return Status::kInvalidConfig;
    }
  }
  // Lateral rows: used (held at zero) when the axes make them real and the rank allows it.
  const double lateral = r.B_.topRows<2>().norm();
  if (n >= 6 && lateral > 1e-6 * r.B_.row(2).norm()) {
    Eigen::JacobiSVD<Eigen::MatrixXd> svd6(r.B_);
    const auto& sv = svd6.singularValues();
    r.lateral_ = sv[5] > kRankTolerance * sv[0] * 1e3;
  }
  const Eigen::MatrixXd Bs = r.lateral_ ? r.B_ : r.A_;
  r.row_T_ = r.lateral_ ? 2 : 0;
  // Exact pseudo-inverse of a full-row-rank matrix: P = Bs^T (Bs Bs^T)^-1.
  const Eigen::MatrixXd G = Bs * Bs.transpose();
  Eigen::FullPivLU<Eigen::MatrixXd> lu(G);
  if (!lu.isInvertible()) {
    if (why) *why = "RotorAllocationConfig: rotor layout cannot produce every wrench (singular)";
    return Status::kInvalidConfig;
  }
  r.P_ = Bs.transpose() * lu.inverse();
  // Collective thrust must raise every rotor (true for any layout around the CoM); the
  // saturation handling shifts thrust along this column.
  r.u_ = r.P_.col(r.row_T_);
  if ((r.u_.array() <= 0.0).any()) {
    if (why) *why = "RotorAllocationConfig: the rotors do not surround the centre of mass "
                    "(hovering would need a negative thrust)";
    return Status::kInvalidConfig;
  }
  r.max_collective_ = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) r.max_collective_ = std::min(r.max_collective_, r.hi_[i] / r.u_[i]);
  for (auto* v : {&r.f_, &r.f_rp_, &r.f_yaw_, &r.prev_}) *v = Eigen::VectorXd::Zero(n);
  r.configured_ = true;
  *out = std::move(r);
  return Status::kOk;
}

Status RotorAllocation::allocate(const Eigen::Vector4d& wrench, Eigen::Ref<Eigen::VectorXd> thrust,
                                 Eigen::Vector4d* achieved) noexcept {
  const double lo = cfg_.thrust_min;
  if (!configured_) {
    thrust.setZero();
    if (achieved) achieved->setZero();
    return Status::kNotConfigured;
  }
  if (thrust.size() != n_) {
    if (achieved) achieved->setZero();
    return Status::kBadSize;
  }
  if (!wrench.allFinite()) {
    thrust.setConstant(lo);
    if (achieved) achieved->noalias() = A_ * thrust;
    return Status::kNonFiniteReference;
  }
  const int t = row_T_;
  Status status = Status::kOk;
  // Unsaturated: f = P [0, 0,] T, tau (the lateral rows, when used, are held at zero).
  // Element by element as Eigen's vector sums took them (u T, then + P_k tau_k for k in order),
  // without their dynamic-size setup on a vector of a few rotors.
  for (int i = 0; i < n_; ++i) {
    double f = u_[i] * wrench[0];
    for (int k = 0; k < 3; ++k) f += P_(i, t + 1 + k) * wrench[1 + k];
    f_[i] = f;
  }
  bool fits = true;
  for (int i = 0; i < n_; ++i) fits = fits && f_[i] >= lo && f_[i] <= hi_[i];
  if (!fits) {
    status = Status::kSaturated;
    f_rp_.noalias() = P_.col(t + 1) * wrench[1];
    f_rp_.noalias() += P_.col(t + 2) * wrench[2];
    // Roll/pitch alone wider than the thrust range: scale them down (the last resort). The
    // largest s in [0, 1] for which some collective fits every rotor: per pair of rotors the
    // collective interval [(lo - s a_i) / u_i, (hi_i - s a_i) / u_i] must intersect.
    double scale = 1.0;
    for (int i = 0; i < n_; ++i) {
      for (int j = 0; j < n_; ++j) {
        // Need (lo - s a_i) / u_i <= (hi_j - s a_j) / u_j, i.e. s (a_j / u_j - a_i / u_i) <=
        // hi_j / u_j - lo / u_i (the right side is > 0 when lo < hi, true by validation).
        const double lhs = f_rp_[j] / u_[j] - f_rp_[i] / u_[i];
        const double rhs = hi_[j] / u_[j] - lo / u_[i];
        if (lhs > rhs) scale = std::min(scale, rhs / lhs);
      }
    }
    if (scale < 1.0) f_rp_ *= std::max(scale, 0.0);
    // Collective thrust: the value nearest the command that keeps every rotor in range.
    double t_lo = -std::numeric_limits<double>::infinity();
    double t_hi = std::numeric_limits<double>::infinity();
    for (int i = 0; i < n_; ++i) {
      t_lo = std::max(t_lo, (lo - f_rp_[i]) / u_[i]);
      t_hi = std::min(t_hi, (hi_[i] - f_rp_[i]) / u_[i]);
    }
    const double collective =
        t_lo <= t_hi ? std::clamp(wrench[0], t_lo, t_hi) : 0.5 * (t_lo + t_hi);
    f_rp_.noalias() += u_ * collective;  // the base: roll/pitch and collective
    // Yaw last: the largest share k in [0, 1] of its thrust pattern that stays in range.
    f_yaw_.noalias() = P_.col(t + 3) * wrench[3];
    double k = 1.0;
    for (int i = 0; i < n_; ++i) {
      if (f_yaw_[i] > 0) k = std::min(k, (hi_[i] - f_rp_[i]) / f_yaw_[i]);
      if (f_yaw_[i] < 0) k = std::min(k, (lo - f_rp_[i]) / f_yaw_[i]);
    }
    k = std::clamp(k, 0.0, 1.0);
    f_ = f_rp_;
    f_.noalias() += k * f_yaw_;
  }
  // Rounding only: after the steps above every thrust is in range up to a few ulps.
  for (int i = 0; i < n_; ++i) f_[i] = std::clamp(f_[i], lo, hi_[i]);
  if (achieved) achieved->noalias() = A_ * f_;
  if (cfg_.lag_compensation && have_prev_) {
    const double lead = cfg_.time_constant / cfg_.dt;
    for (int i = 0; i < n_; ++i)
      thrust[i] = std::clamp(f_[i] + lead * (f_[i] - prev_[i]), lo, hi_[i]);
  } else {
    thrust = f_;
  }
  prev_ = f_;
  have_prev_ = true;
  return status;
}

}  // namespace kiloloop
