#include "kiloloop/calibration/kinematic_calibration.hpp"

#include <cmath>

#include <Eigen/SVD>

namespace kiloloop {

Status validate(const CalibrationConfig& c, std::string* why) {
  auto fail = [why](const char* msg) {
    if (why) *why = msg;
    return Status::kInvalidConfig;
  };
  if (c.max_iterations < 1) return fail("max_iterations must be >= 1");
  if (!(c.step_tolerance >= 0.0)) return fail("step_tolerance must be >= 0");
  if (!(c.rank_tolerance > 0.0 && c.rank_tolerance < 1.0)) return fail("rank_tolerance must be in (0, 1)");
  if (!(c.finite_difference > 0.0 && c.finite_difference < 1e-2))
    return fail("finite_difference must be in (0, 1e-2)");
  if (!(c.length_range > 0.0 && std::isfinite(c.length_range))) return fail("length_range must be > 0");
  if (!(c.angle_range > 0.0 && std::isfinite(c.angle_range))) return fail("angle_range must be > 0");
  return Status::kOk;
}

void position_residuals(const KinematicParameters& params, const Eigen::MatrixXd& q,
                        const Eigen::MatrixXd& p, double* rms, double* max) {
  double sum = 0.0, worst = 0.0;
  for (int k = 0; k < q.cols(); ++k) {
    const double e = (p.col(k) - params.position(q.col(k))).norm();
    sum += e * e;
    worst = std::max(worst, e);
  }
  *rms = q.cols() ? std::sqrt(sum / q.cols()) : 0.0;
  *max = worst;
}

namespace {

// Indices into pack() of the parameters to identify.
std::vector<int> free_parameters(const KinematicParameters& k, bool beta) {
  const int n = k.nq();
  std::vector<int> idx;
  for (int i = 0; i < 6; ++i) idx.push_back(i);
  for (int block = 0; block < 5; ++block) {
    for (int i = 0; i < n; ++i) {
      if (block == 2 && !(beta && k.has_beta[i])) continue;
      idx.push_back(6 + block * n + i);
    }
  }
  for (int i = 0; i < 3; ++i) idx.push_back(6 + 5 * n + i);
  return idx;
}

// True for the pack() entries that are lengths (base position, a, d, tool), false for angles.
bool is_length(const KinematicParameters& k, int index) {
  const int n = k.nq();
  if (index < 3) return true;
  if (index < 6) return false;
  const int block = (index - 6) / n;  // 0 alpha, 1 a, 2 beta, 3 theta, 4 d, 5.. tool
  return block == 1 || block >= 4;
}

Eigen::VectorXd residual(const KinematicParameters& k, const Eigen::MatrixXd& q,
                         const Eigen::MatrixXd& p) {
  Eigen::VectorXd r(3 * q.cols());
  for (int j = 0; j < q.cols(); ++j) r.segment<3>(3 * j) = p.col(j) - k.position(q.col(j));
  return r;
}

}  // namespace

Status calibrate_kinematics(const KinematicParameters& nominal, const Eigen::MatrixXd& q,
                            const Eigen::MatrixXd& p, const CalibrationConfig& config,
                            CalibrationResult* result, std::string* why) {
  Status s = validate(config, why);
  if (failed(s)) return s;
  const int n = nominal.nq(), m = static_cast<int>(q.cols());
  if (q.rows() != n || p.rows() != 3 || p.cols() != m || m < 1) {
    if (why) *why = "calibration data: q must be (n, m) and p (3, m)";
    return Status::kBadSize;
  }
  if (!q.allFinite() || !p.allFinite()) {
    if (why) *why = "calibration data must be finite";
    return Status::kNonFiniteMeasurement;
  }
  const std::vector<int> idx = free_parameters(nominal, config.identify_beta);
  const int np = static_cast<int>(idx.size());
  CalibrationResult res;
  res.num_parameters = np;
  KinematicParameters k = nominal;
  Eigen::VectorXd x = k.pack();
  double dummy;
  position_residuals(nominal, q, p, &res.rms_residual_nominal, &dummy);
  Eigen::MatrixXd J(3 * m, np);
  Eigen::VectorXd scale(np), sv;
  // O1's column scale: the parameter's fixed range, with the point motion expressed in mm.
  Eigen::VectorXd range(np);
  for (int c = 0; c < np; ++c)
    range[c] = (is_length(nominal, idx[c]) ? config.length_range : config.angle_range) / 1e-3;
  Eigen::MatrixXd J_range(3 * m, np);
  for (int it = 0; it < config.max_iterations; ++it) {
    const Eigen::VectorXd r = residual(k, q, p);
    // dr/dx = -dp/dx; central differences.
    for (int c = 0; c < np; ++c) {
      KinematicParameters kp = k, km = k;
      Eigen::VectorXd xp = x, xm = x;
      xp[idx[c]] += config.finite_difference;
      xm[idx[c]] -= config.finite_difference;
      kp.unpack(xp);
      km.unpack(xm);
      for (int j = 0; j < m; ++j)
        J.block<3, 1>(3 * j, c) = (kp.position(q.col(j)) - km.position(q.col(j))) / (2 * config.finite_difference);
      J_range.col(c) = J.col(c) * range[c];
      scale[c] = J.col(c).norm();
      if (scale[c] > 0.0) J.col(c) /= scale[c];
    }
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeThinU | Eigen::ComputeThinV);
    sv = svd.singularValues();
    const double cut = config.rank_tolerance * sv[0];
    int rank = 0;
    while (rank < sv.size() && sv[rank] > cut) ++rank;
    // Truncated pseudo-inverse: no motion along unobservable directions.
    Eigen::VectorXd y = svd.matrixU().leftCols(rank).transpose() * r;
    y.array() /= sv.head(rank).array();
    const Eigen::VectorXd step_scaled = svd.matrixV().leftCols(rank) * y;
    for (int c = 0; c < np; ++c)
      if (scale[c] > 0.0) x[idx[c]] += step_scaled[c] / scale[c];
    k.unpack(x);
    res.iterations = it + 1;
    res.rank = rank;
    res.condition_number = sv[0] / sv[rank - 1];
    // Column scaling keeps the rank: the r largest range-scaled singular values are the
    // observable directions.
    const Eigen::VectorXd sv_range = Eigen::JacobiSVD<Eigen::MatrixXd>(J_range).singularValues();
    double log_sum = 0.0;
    for (int i = 0; i < rank; ++i) log_sum += std::log(sv_range[i]);
    res.observability_index = std::exp(log_sum / rank) / std::sqrt(static_cast<double>(m));
    if (step_scaled.norm() < config.step_tolerance) break;
  }
  if (!x.allFinite()) {
    if (why) *why = "calibration diverged";
    return Status::kSolverFailed;
  }
  res.parameters = k;
  position_residuals(k, q, p, &res.rms_residual, &dummy);
  *result = res;
  return Status::kOk;
}

}  // namespace kiloloop
