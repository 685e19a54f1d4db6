#pragma once
// Least-squares identification of the kinematic parameters (kinematic_parameters.hpp) from
// measured positions of a point on the end effector (laser tracker, CMM): Gauss-Newton on
//   r(x) = [p_meas_k - p(q_k; x)]_k                      (3 m)  [m]
// with the identification Jacobian by central differences (offline, any chain), columns scaled
// to unit norm, and a truncated SVD pseudo-inverse: singular values below
// `rank_tolerance * sigma_max` are directions the data cannot observe (parameters that are
// exactly redundant, such as a base rotation about joint 1's axis vs theta_1); they are left at
// their nominal values. Observability figures of the final Jacobian are reported:
//   condition number  sigma_max / sigma_min of the unit-norm-column Jacobian over the retained
//                     directions (1 is ideal)
//   O1 index          (sigma_1 ... sigma_r)^(1/r) / sqrt(m)  (Borm & Menq 1991) over the same r
//                     directions, of the Jacobian with columns scaled by FIXED parameter ranges
//                     (`length_range`, `angle_range`), in mm: the RMS point motion per pose for a
//                     parameter change of one range. Unit-norm columns would not do: their
//                     singular values do not grow with m, so O1 would fall as 1/sqrt(m).
#include <string>

#include <Eigen/Core>

#include "kiloloop/calibration/kinematic_parameters.hpp"

namespace kiloloop {

struct CalibrationConfig {
  int max_iterations = 20;       // Gauss-Newton iterations
  double step_tolerance = 1e-12; // [scaled] stop when the step norm falls below
  double rank_tolerance = 1e-5;  // relative singular-value cut-off: far above the
                                 // finite-difference noise (~1e-9), far below real
                                 // directions (UR5: sigma_min / sigma_max ~ 0.2)
  double finite_difference = 1e-7;  // [m or rad] central-difference step
  bool identify_beta = true;     // false: plain modified DH (for comparison)
  // Parameter ranges that scale the Jacobian's columns for O1 only (not for the solve).
  double length_range = 1e-3;    // [m]
  double angle_range = 1e-3;     // [rad]
};

Status validate(const CalibrationConfig& config, std::string* why);

struct CalibrationResult {
  KinematicParameters parameters;  // identified
  int iterations = 0;
  int num_parameters = 0;          // free parameters considered
  int rank = 0;                    // observable directions among them
  double condition_number = 0.0;   // of the unit-norm-column identification Jacobian (retained)
  double observability_index = 0.0;  // O1 with range-scaled columns [mm per range, per pose]
  double rms_residual = 0.0;       // [m] per measured point, on the identification data
  double rms_residual_nominal = 0.0;  // [m] the same with the nominal parameters
};

// q: (n, m) joint configurations in columns; p: (3, m) measured positions [m].
Status calibrate_kinematics(const KinematicParameters& nominal, const Eigen::MatrixXd& q,
                            const Eigen::MatrixXd& p, const CalibrationConfig& config,
                            CalibrationResult* result, std::string* why);

// RMS and max of |p_k - p(q_k; params)| over the columns [m].
void position_residuals(const KinematicParameters& params, const Eigen::MatrixXd& q,
                        const Eigen::MatrixXd& p, double* rms, double* max);

}  // namespace kiloloop
