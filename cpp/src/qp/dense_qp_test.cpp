#include "kiloloop/qp/dense_qp.hpp"
#include "test_values.hpp"

#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"

namespace kiloloop::qp {
namespace {


struct Qp {
  Eigen::MatrixXd H, A, C;
  Eigen::VectorXd g, b, d, lb, ub;
};

struct Solution {
  QpResult res;
  Eigen::VectorXd x, lambda, mu, z;
};

Solution solve(DenseQpSolver& solver, const Qp& qp) {
  Solution s;
  s.x = Eigen::VectorXd::Zero(qp.H.rows());
  s.res = solver.solve(qp.H, qp.g, qp.A, qp.b, qp.C, qp.d, qp.lb, qp.ub, s.x);
  s.lambda = solver.eq_multipliers();
  s.mu = solver.ineq_multipliers();
  s.z = solver.bound_multipliers();
  return s;
}

DenseQpSolver make_solver(int n, int me, int mi, QpSettings settings = {}) {
  DenseQpSolver solver;
  std::string why;
  EXPECT_EQ(DenseQpSolver::configure(n, me, mi, settings, &solver, &why), Status::kOk) << why;
  return solver;
}

Qp empty_qp(int n) {
  Qp qp;
  qp.H = Eigen::MatrixXd::Identity(n, n);
  qp.g = Eigen::VectorXd::Zero(n);
  qp.A.resize(0, n);
  qp.b.resize(0);
  qp.C.resize(0, n);
  qp.d.resize(0);
  return qp;
}

// A random feasible problem: constraints built around a point x0, about half of them tight there
// (so they tend to be active), with optional bounds; H = M M' + 0.1 I.
Qp random_feasible(std::mt19937& rng, int n, int me, int mi, bool bounds,
                   Eigen::VectorXd* point = nullptr) {
  std::normal_distribution<double> N(0.0, 1.0);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto randn = [&](int r, int c) {
    Eigen::MatrixXd m(r, c);
    for (int j = 0; j < c; ++j)
      for (int i = 0; i < r; ++i) m(i, j) = N(rng);
    return m;
  };
  Qp qp;
  const Eigen::MatrixXd M = randn(n, n);
  qp.H = M * M.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
  qp.g = 5.0 * randn(n, 1);
  const Eigen::VectorXd x0 = randn(n, 1);
  if (point) *point = x0;
  qp.A = randn(me, n);
  qp.b = qp.A * x0;
  qp.C = randn(mi, n);
  qp.d = qp.C * x0;
  for (int i = 0; i < mi; ++i) {
    if (U(rng) < 0.5) qp.d[i] += U(rng);
  }
  if (bounds) {  // lb <= x0 <= ub, some sides tight, some infinite
    qp.lb = x0;
    qp.ub = x0;
    for (int j = 0; j < n; ++j) {
      if (U(rng) < 0.5) {
        qp.lb[j] -= U(rng);
      }
      if (U(rng) < 0.5) {
        qp.ub[j] += U(rng);
      }
      if (U(rng) < 0.2) {
        qp.lb[j] = -kInf;
      }
      if (U(rng) < 0.2) {
        qp.ub[j] = kInf;
      }
    }
  }
  return qp;
}

// Optimality certificate for the convex QP: primal feasibility, dual feasibility, complementary
// slackness and stationarity H x + g + A' lambda + C' mu + z = 0.
void expect_kkt(const Qp& qp, const Solution& s, double tol = 1e-8) {
  ASSERT_EQ(s.res.status, QpStatus::kOptimal);
  const int n = static_cast<int>(qp.H.rows());
  const double scale = 1.0 + s.x.cwiseAbs().maxCoeff();
  if (qp.A.rows() > 0) {
    EXPECT_LE((qp.A * s.x - qp.b).cwiseAbs().maxCoeff(), tol * scale);
  }
  Eigen::VectorXd residual = qp.H * s.x + qp.g;
  if (qp.A.rows() > 0) residual += qp.A.transpose() * s.lambda;
  if (qp.C.rows() > 0) {
    const Eigen::VectorXd slack = qp.d - qp.C * s.x;
    EXPECT_GE(slack.minCoeff(), -tol * scale);
    EXPECT_GE(s.mu.minCoeff(), 0.0);
    for (int i = 0; i < qp.C.rows(); ++i)
      EXPECT_LE(s.mu[i] * std::abs(slack[i]), tol * scale * (1.0 + s.mu[i])) << "row " << i;
    residual += qp.C.transpose() * s.mu;
  }
  ASSERT_EQ(s.z.size(), n);
  residual += s.z;
  for (int j = 0; j < n; ++j) {
    const double lo = qp.lb.size() ? qp.lb[j] : -kInf, hi = qp.ub.size() ? qp.ub[j] : kInf;
    EXPECT_GE(s.x[j], lo - tol * scale);
    EXPECT_LE(s.x[j], hi + tol * scale);
    if (s.z[j] > 0.0) {
      EXPECT_LE(s.z[j] * (hi - s.x[j]), tol * scale * (1.0 + s.z[j]));
    } else if (s.z[j] < 0.0) {
      EXPECT_LE(-s.z[j] * (s.x[j] - lo), tol * scale * (1.0 - s.z[j]));
    }
  }
  const double g_scale = 1.0 + qp.g.cwiseAbs().maxCoeff() + qp.H.cwiseAbs().maxCoeff() * scale;
  EXPECT_LE(residual.cwiseAbs().maxCoeff(), tol * g_scale);
}

TEST(DenseQp, ConfigureRejectsBadSettings) {
  DenseQpSolver s;
  std::string why;
  EXPECT_EQ(DenseQpSolver::configure(0, 0, 0, {}, &s, &why), Status::kInvalidConfig);
  EXPECT_EQ(DenseQpSolver::configure(3, -1, 0, {}, &s, &why), Status::kInvalidConfig);
  QpSettings bad;
  bad.max_iterations = 0;
  EXPECT_EQ(DenseQpSolver::configure(3, 0, 0, bad, &s, &why), Status::kInvalidConfig);
  bad = {};
  bad.feasibility_tol = std::nan("");
  EXPECT_EQ(DenseQpSolver::configure(3, 0, 0, bad, &s, &why), Status::kInvalidConfig);
  EXPECT_EQ(DenseQpSolver::configure(3, 0, 0, {}, nullptr, &why), Status::kInvalidConfig);
}

TEST(DenseQp, UnconstrainedAndBoxSolutions) {
  DenseQpSolver solver = make_solver(3, 1, 2);
  Qp qp = empty_qp(3);
  qp.H.diagonal() << 1.0, 2.0, 4.0;
  qp.g << -1.0, -4.0, 8.0;  // unconstrained minimum (1, 2, -2)
  Solution s = solve(solver, qp);
  EXPECT_EQ(s.res.status, QpStatus::kOptimal);
  EXPECT_EQ(s.res.iterations, 0);
  EXPECT_TRUE(s.x.isApprox(Eigen::Vector3d(1.0, 2.0, -2.0), 1e-15));
  EXPECT_NEAR(s.res.objective, -0.5 - 4.0 - 8.0, 1e-12);

  qp.lb = Eigen::Vector3d(-kInf, -kInf, -1.0);
  qp.ub = Eigen::Vector3d(0.5, kInf, kInf);
  s = solve(solver, qp);
  EXPECT_TRUE(s.x.isApprox(Eigen::Vector3d(0.5, 2.0, -1.0), 1e-15));
  EXPECT_EQ(s.res.n_active, 2);
  EXPECT_NEAR(s.z[0], 0.5, 1e-14);   // upper bound: z > 0
  EXPECT_NEAR(s.z[2], -4.0, 1e-14);  // lower bound: z < 0
  expect_kkt(qp, s);

  // Equality x0 + x1 + x2 = 0 plus a row x1 <= 1 that is active at the solution.
  qp.A = Eigen::RowVector3d(1.0, 1.0, 1.0);
  qp.b = Eigen::VectorXd::Zero(1);
  qp.C = Eigen::RowVector3d(0.0, 1.0, 0.0);
  qp.d = Eigen::VectorXd::Ones(1);
  s = solve(solver, qp);
  expect_kkt(qp, s);
  EXPECT_NEAR(s.x.sum(), 0.0, 1e-14);
}

TEST(DenseQp, RandomFeasibleProblemsSatisfyKkt) {
  const unsigned seed = 20261122;
  std::cout << "seed " << seed << "\n";
  std::mt19937 rng(seed);
  DenseQpSolver solver = make_solver(30, 10, 60);
  const int shapes[][3] = {{2, 0, 3}, {5, 2, 8}, {12, 0, 16}, {12, 6, 16}, {20, 5, 40}, {30, 10, 60},
                           {8, 8, 12}, {6, 0, 30}};
  int total_iterations = 0, problems = 0;
  for (const auto& shape : shapes) {
    for (int k = 0; k < 150; ++k) {
      const Qp qp = random_feasible(rng, shape[0], shape[1], shape[2], k % 2 == 0);
      const Solution s = solve(solver, qp);
      SCOPED_TRACE(::testing::Message() << "n " << shape[0] << " problem " << k);
      expect_kkt(qp, s);
      total_iterations += s.res.iterations;
      ++problems;
      if (::testing::Test::HasFailure()) return;
    }
  }
  std::cout << problems << " problems, " << total_iterations << " iterations\n";
}

TEST(DenseQp, DegenerateConstraints) {
  const unsigned seed = 7;
  std::cout << "seed " << seed << "\n";
  std::mt19937 rng(seed);
  DenseQpSolver solver = make_solver(10, 12, 40);
  for (int k = 0; k < 300; ++k) {
    SCOPED_TRACE(::testing::Message() << "problem " << k);
    Eigen::VectorXd x0;
    Qp qp = random_feasible(rng, 8, 3, 10, true, &x0);
    const int n = 8;
    // Duplicated and scaled rows, a row duplicating a bound, an equality repeated as two rows.
    Eigen::MatrixXd C(qp.C.rows() + 6, n);
    Eigen::VectorXd d(qp.d.size() + 6);
    C << qp.C, qp.C.row(0), 2.0 * qp.C.row(1), Eigen::RowVectorXd::Unit(n, 2),
        -Eigen::RowVectorXd::Unit(n, 3), qp.A.row(0), -qp.A.row(0);
    d << qp.d, qp.d[0], 2.0 * qp.d[1], std::isfinite(qp.ub[2]) ? qp.ub[2] : x0[2] + 1.0,
        std::isfinite(qp.lb[3]) ? -qp.lb[3] : -x0[3] + 1.0, qp.b[0], -qp.b[0];
    qp.C = C;
    qp.d = d;
    // A duplicated (scaled) equality; a fixed variable (lb == ub) every third problem.
    Eigen::MatrixXd A(qp.A.rows() + 1, n);
    A << qp.A, 3.0 * qp.A.row(1);
    Eigen::VectorXd b(qp.b.size() + 1);
    b << qp.b, 3.0 * qp.b[1];
    qp.A = A;
    qp.b = b;
    if (k % 3 == 0) qp.lb[5] = qp.ub[5] = x0[5];
    expect_kkt(qp, solve(solver, qp));
    if (::testing::Test::HasFailure()) return;
  }
}

TEST(DenseQp, ConstraintsActiveAtTheUnconstrainedOptimum) {
  DenseQpSolver solver = make_solver(4, 2, 8);
  Qp qp = empty_qp(4);
  qp.g << 1.0, -2.0, 0.5, 0.0;  // unconstrained minimum (-1, 2, -0.5, 0)
  const Eigen::Vector4d x_unc(-1.0, 2.0, -0.5, 0.0);
  qp.C.resize(4, 4);
  qp.C << 1, 0, 0, 0, 0, 1, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1;
  qp.d = qp.C * x_unc;  // every row tight at the start, one duplicated
  qp.A = Eigen::RowVector4d(0, 0, 0, 1);
  qp.b = Eigen::VectorXd::Zero(1);
  qp.lb = x_unc;
  qp.ub = x_unc + Eigen::Vector4d::Ones();
  const Solution s = solve(solver, qp);
  expect_kkt(qp, s);
  EXPECT_TRUE(s.x.isApprox(x_unc, 1e-15));
  EXPECT_EQ(s.res.n_active, 0);
}

TEST(DenseQp, ParallelConstraintsAndMoreEqualitiesThanVariables) {
  DenseQpSolver solver = make_solver(3, 6, 6);
  Qp qp = empty_qp(3);
  qp.g << -10.0, -10.0, -10.0;
  // x0 + x1 <= 1, 2 x0 + 2 x1 <= 1 (tighter, parallel), -x0 - x1 <= 5 (opposite side).
  qp.C.resize(3, 3);
  qp.C << 1, 1, 0, 2, 2, 0, -1, -1, 0;
  qp.d = Eigen::Vector3d(1.0, 1.0, 5.0);
  Solution s = solve(solver, qp);
  expect_kkt(qp, s);
  EXPECT_NEAR(s.x[0] + s.x[1], 0.5, 1e-14);
  EXPECT_NEAR(s.mu[0], 0.0, 1e-14);
  // Five consistent equalities of rank 3 on top: the dependent ones are redundant.
  qp.A.resize(5, 3);
  qp.A << 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 0, 1, 2, 2, 1;
  const Eigen::Vector3d x_eq(0.1, 0.2, 3.0);
  qp.b = qp.A * x_eq;
  s = solve(solver, qp);
  expect_kkt(qp, s);
  EXPECT_TRUE(s.x.isApprox(x_eq, 1e-14));
}

TEST(DenseQp, FixedVariablesAreEliminatedExactly) {
  const unsigned seed = 11;
  std::cout << "seed " << seed << "\n";
  std::mt19937 rng(seed);
  QpSettings cold_settings;
  cold_settings.warm_start = false;
  DenseQpSolver warm = make_solver(12, 8, 16), cold = make_solver(12, 8, 16, cold_settings);
  const int fixed_sets[2][3] = {{0, 1, 2}, {6, 7, 8}};  // alternating, like a trot's swing legs
  for (int k = 0; k < 200; ++k) {
    SCOPED_TRACE(::testing::Message() << "problem " << k);
    Eigen::VectorXd x0;
    Qp qp = random_feasible(rng, 12, 2, 16, true, &x0);
    // The same problem twice: fixed variables as lb == ub, and as equality rows.
    Qp as_rows = qp;
    as_rows.A.conservativeResize(5, 12);
    as_rows.b.conservativeResize(5);
    for (int i = 0; i < 3; ++i) {
      const int j = fixed_sets[(k / 10) % 2][i];
      qp.lb[j] = qp.ub[j] = x0[j];
      as_rows.A.row(2 + i) = Eigen::RowVectorXd::Unit(12, j);
      as_rows.b[2 + i] = x0[j];
    }
    const Solution s = solve(warm, qp), c = solve(cold, qp), r = solve(cold, as_rows);
    expect_kkt(qp, s);
    expect_kkt(as_rows, r);
    EXPECT_LE((s.x - r.x).cwiseAbs().maxCoeff(), 1e-9 * (1.0 + r.x.cwiseAbs().maxCoeff()));
    EXPECT_LE((s.x - c.x).cwiseAbs().maxCoeff(), 1e-10 * (1.0 + c.x.cwiseAbs().maxCoeff()));
    for (int i = 0; i < 3; ++i) {
      const int j = fixed_sets[(k / 10) % 2][i];
      EXPECT_EQ(s.x[j], x0[j]);  // exactly the fixed value (its multiplier: KKT above)
    }
    EXPECT_GE(s.res.n_active, 3);  // fixed variables count as active bounds
    if (::testing::Test::HasFailure()) return;
  }
  // Every variable fixed: nothing to eliminate; they become equalities.
  Qp all = empty_qp(3);
  all.lb = all.ub = Eigen::Vector3d(1.0, -2.0, 0.5);
  all.C = Eigen::RowVector3d(1.0, 1.0, 1.0);
  all.d = Eigen::VectorXd::Constant(1, 0.0);
  Solution s = solve(cold, all);
  expect_kkt(all, s);
  EXPECT_EQ(s.x, all.lb);
  all.d[0] = -1.0;  // 1 - 2 + 0.5 = -0.5 > -1
  EXPECT_EQ(solve(cold, all).res.status, QpStatus::kInfeasible);
}

TEST(DenseQp, InfeasibleProblems) {
  DenseQpSolver solver = make_solver(3, 3, 4);
  Qp qp = empty_qp(3);
  // x0 <= 0 and x0 >= 1 as rows.
  qp.C.resize(2, 3);
  qp.C << 1, 0, 0, -1, 0, 0;
  qp.d = Eigen::Vector2d(0.0, -1.0);
  EXPECT_EQ(solve(solver, qp).res.status, QpStatus::kInfeasible);
  // ... as bounds (lb > ub).
  qp = empty_qp(3);
  qp.lb = Eigen::Vector3d(1.0, -kInf, -kInf);
  qp.ub = Eigen::Vector3d(0.0, kInf, kInf);
  EXPECT_EQ(solve(solver, qp).res.status, QpStatus::kInfeasible);
  // Contradictory equalities.
  qp = empty_qp(3);
  qp.A.resize(2, 3);
  qp.A << 1, 1, 0, 2, 2, 0;
  qp.b = Eigen::Vector2d(1.0, 3.0);
  EXPECT_EQ(solve(solver, qp).res.status, QpStatus::kInfeasible);
  // An equality against an inequality: x0 + x1 = 1, x0 <= 0, x1 <= 0.
  qp.A = Eigen::RowVector3d(1, 1, 0);
  qp.b = Eigen::VectorXd::Ones(1);
  qp.C.resize(2, 3);
  qp.C << 1, 0, 0, 0, 1, 0;
  qp.d = Eigen::Vector2d::Zero();
  const Solution s = solve(solver, qp);
  EXPECT_EQ(s.res.status, QpStatus::kInfeasible);
  EXPECT_TRUE(s.x.allFinite());
  // A triangle cut away by a third halfspace: x0 >= 0, x1 >= 0, x0 + x1 <= -1 (as rows).
  qp = empty_qp(3);
  qp.C.resize(3, 3);
  qp.C << -1, 0, 0, 0, -1, 0, 1, 1, 0;
  qp.d = Eigen::Vector3d(0.0, 0.0, -1.0);
  EXPECT_EQ(solve(solver, qp).res.status, QpStatus::kInfeasible);
  // A zero row with a negative right-hand side.
  qp = empty_qp(3);
  qp.C = Eigen::MatrixXd::Zero(1, 3);
  qp.d = -Eigen::VectorXd::Ones(1);
  EXPECT_EQ(solve(solver, qp).res.status, QpStatus::kInfeasible);
}

TEST(DenseQp, BadInputIsReportedNotCrashed) {
  DenseQpSolver unconfigured;
  Qp qp = empty_qp(3);
  Eigen::VectorXd x = Eigen::VectorXd::Ones(3);
  EXPECT_EQ(unconfigured.solve(qp.H, qp.g, qp.A, qp.b, qp.C, qp.d, qp.lb, qp.ub, x).status,
            QpStatus::kNotConfigured);

  DenseQpSolver solver = make_solver(3, 1, 2);
  auto status = [&](const Qp& p) { return solve(solver, p).res.status; };
  EXPECT_EQ(status(empty_qp(4)), QpStatus::kBadInput);  // n beyond the workspace
  Qp bad = empty_qp(3);
  bad.C = Eigen::MatrixXd::Ones(3, 3);  // more rows than max_ineq
  bad.d = Eigen::VectorXd::Ones(3);
  EXPECT_EQ(status(bad), QpStatus::kBadInput);
  bad = empty_qp(3);
  bad.C = Eigen::MatrixXd::Ones(1, 2);  // wrong column count
  bad.d = Eigen::VectorXd::Ones(1);
  EXPECT_EQ(status(bad), QpStatus::kBadInput);
  bad = empty_qp(3);
  bad.A = Eigen::MatrixXd::Ones(1, 3);
  bad.b = Eigen::VectorXd::Ones(2);  // b_eq size
  EXPECT_EQ(status(bad), QpStatus::kBadInput);
  bad = empty_qp(3);
  bad.lb = Eigen::VectorXd::Zero(2);
  EXPECT_EQ(status(bad), QpStatus::kBadInput);
  bad = empty_qp(3);
  bad.H(1, 1) = std::nan("");
  EXPECT_EQ(status(bad), QpStatus::kBadInput);
  bad = empty_qp(3);
  bad.g[0] = kInf;
  EXPECT_EQ(status(bad), QpStatus::kBadInput);
  bad = empty_qp(3);
  bad.C = Eigen::MatrixXd::Ones(1, 3);
  bad.d = Eigen::VectorXd::Constant(1, -kInf);  // C x <= -inf can never be met
  EXPECT_EQ(status(bad), QpStatus::kInfeasible);
  bad.d[0] = kInf;  // +inf: the row is ignored
  EXPECT_EQ(status(bad), QpStatus::kOptimal);
  bad.C(0, 1) = std::nan("");
  EXPECT_EQ(status(bad), QpStatus::kBadInput);
  bad = empty_qp(3);
  bad.lb = Eigen::VectorXd::Constant(3, kInf);  // x >= +inf can never be met
  EXPECT_EQ(status(bad), QpStatus::kInfeasible);
  bad.lb = Eigen::VectorXd::Constant(3, std::nan(""));  // NaN is bad data, not a bound
  EXPECT_EQ(status(bad), QpStatus::kBadInput);
  bad = empty_qp(3);
  bad.H(0, 2) = bad.H(2, 0) = kInf;  // inf off the diagonal, symmetric
  EXPECT_EQ(status(bad), QpStatus::kBadInput);
  bad = empty_qp(3);
  bad.H(2, 2) = -1.0;  // indefinite
  EXPECT_EQ(status(bad), QpStatus::kBadInput);
  bad.H(2, 2) = 0.0;  // semidefinite
  EXPECT_EQ(status(bad), QpStatus::kBadInput);
  bad = empty_qp(3);
  bad.H(0, 1) = 0.5;  // not symmetric
  EXPECT_EQ(status(bad), QpStatus::kBadInput);
  // x of the wrong size is left alone; x of the right size is zeroed on bad input.
  bad = empty_qp(3);
  bad.g[1] = std::nan("");
  Eigen::VectorXd x2 = Eigen::VectorXd::Ones(2);
  EXPECT_EQ(solver.solve(bad.H, bad.g, bad.A, bad.b, bad.C, bad.d, bad.lb, bad.ub, x2).status,
            QpStatus::kBadInput);
  EXPECT_EQ(x2, Eigen::VectorXd::Ones(2));
  EXPECT_EQ(solver.solve(bad.H, bad.g, bad.A, bad.b, bad.C, bad.d, bad.lb, bad.ub, x).status,
            QpStatus::kBadInput);
  EXPECT_EQ(x, Eigen::VectorXd::Zero(3));
  EXPECT_EQ(solver.eq_multipliers().size(), 0);
}

// The data of issue 12 and its relatives at the edge of double range: never kOptimal with a
// non-finite or constraint-violating x; x always finite.
TEST(DenseQp, NeverClaimsOptimalWithABadSolution) {
  DenseQpSolver solver = make_solver(3, 1, 2);
  const double denormal = 4.9e-324, huge = 1e308;
  auto check = [&](const Qp& qp, const char* what) {
    const Solution s = solve(solver, qp);
    EXPECT_TRUE(s.x.allFinite()) << what;
    EXPECT_TRUE(std::isfinite(s.res.objective)) << what;
    EXPECT_TRUE(s.lambda.allFinite() && s.mu.allFinite() && s.z.allFinite()) << what;
    if (s.res.status == QpStatus::kOptimal) {
      const double xi = s.x.cwiseAbs().maxCoeff();
      if (qp.C.rows() > 0)
        EXPECT_LE(((qp.C * s.x - qp.d).array()).maxCoeff(), 1e-8 * (qp.d.cwiseAbs().maxCoeff() + 3 * xi)) << what;
      if (qp.lb.size() > 0) EXPECT_TRUE((s.x.array() >= qp.lb.array() - 1e-8 * (1 + xi)).all()) << what;
      if (qp.ub.size() > 0) EXPECT_TRUE((s.x.array() <= qp.ub.array() + 1e-8 * (1 + xi)).all()) << what;
    }
    return s.res.status;
  };
  Qp qp = empty_qp(3);
  qp.C = Eigen::MatrixXd::Identity(1, 3);
  qp.d = Eigen::VectorXd::Constant(1, -huge);  // x0 <= -1e308: the bound
  EXPECT_NE(check(qp, "d = -1e308"), QpStatus::kOptimal);
  qp = empty_qp(3);
  qp.H = denormal * Eigen::MatrixXd::Identity(3, 3);  // the denormal Hessian
  EXPECT_EQ(check(qp, "denormal H"), QpStatus::kBadInput);
  qp = empty_qp(3);
  qp.H = 1e-300 * Eigen::MatrixXd::Identity(3, 3);  // tiny but normal H: x = -g / 1e-300
  qp.g = Eigen::Vector3d(1.0, -1.0, 1.0);
  EXPECT_EQ(check(qp, "tiny H"), QpStatus::kOptimal);  // x = -+1e300: representable, correct
  qp.g = Eigen::Vector3d(1e10, -1e10, 1e10);
  EXPECT_EQ(check(qp, "tiny H, x overflows"), QpStatus::kNumericalError);
  qp = empty_qp(3);
  qp.g = Eigen::Vector3d(huge, -huge, huge);  // x = -g is fine, the objective overflows
  EXPECT_NE(check(qp, "g = 1e308"), QpStatus::kOptimal);
  qp = empty_qp(3);
  qp.ub = Eigen::Vector3d(-huge, 0.0, 0.0);
  qp.g = Eigen::Vector3d(1.0, 1.0, 1.0);
  EXPECT_NE(check(qp, "ub = -1e308"), QpStatus::kOptimal);
  qp = empty_qp(3);
  qp.C = Eigen::MatrixXd::Constant(1, 3, 1e200);  // row norm^2 overflows: still selected
  qp.d = Eigen::VectorXd::Constant(1, -1e200);
  check(qp, "C = 1e200");
  qp = empty_qp(3);
  qp.C = Eigen::MatrixXd::Constant(1, 3, denormal);  // row norm^2 underflows
  qp.d = Eigen::VectorXd::Constant(1, -1.0);
  EXPECT_EQ(check(qp, "C denormal"), QpStatus::kInfeasible);
  qp = empty_qp(3);
  qp.A = Eigen::MatrixXd::Ones(1, 3);
  qp.b = Eigen::VectorXd::Constant(1, huge);
  check(qp, "b = 1e308");
  qp = empty_qp(3);
  qp.lb = Eigen::Vector3d(huge, -kInf, -kInf);
  check(qp, "lb = 1e308");
  qp = empty_qp(3);
  qp.ub = Eigen::Vector3d(-kInf, kInf, kInf);
  EXPECT_EQ(check(qp, "ub = -inf"), QpStatus::kInfeasible);
}

TEST(DenseQp, IterationLimitReturnsTheLastIterate) {
  QpSettings settings;
  settings.max_iterations = 1;
  DenseQpSolver solver = make_solver(3, 0, 0, settings);
  Qp qp = empty_qp(3);
  qp.g = Eigen::Vector3d(-1.0, -1.0, -1.0);
  qp.ub = Eigen::Vector3d::Zero();
  const Solution s = solve(solver, qp);
  EXPECT_EQ(s.res.status, QpStatus::kIterationLimit);
  EXPECT_EQ(s.res.iterations, 1);
  EXPECT_TRUE(s.x.allFinite());
}

TEST(DenseQp, WarmStartChangesIterationsNotSolutions) {
  const unsigned seed = 99;
  std::cout << "seed " << seed << "\n";
  std::mt19937 rng(seed);
  std::normal_distribution<double> N(0.0, 1.0);
  QpSettings cold_settings;
  cold_settings.warm_start = false;
  DenseQpSolver warm = make_solver(12, 6, 16), cold = make_solver(12, 6, 16, cold_settings);
  int warm_iterations = 0, cold_iterations = 0;
  Qp qp = random_feasible(rng, 12, 2, 16, true);
  for (int k = 0; k < 500; ++k) {
    // A slowly drifting problem, as from one control tick to the next.
    for (int j = 0; j < 12; ++j) qp.g[j] += 0.05 * N(rng);
    if (k % 50 == 0) warm.reset_warm_start();
    const Solution w = solve(warm, qp), c = solve(cold, qp);
    ASSERT_EQ(w.res.status, QpStatus::kOptimal);
    ASSERT_EQ(c.res.status, QpStatus::kOptimal);
    EXPECT_LE((w.x - c.x).cwiseAbs().maxCoeff(), 1e-10 * (1.0 + c.x.cwiseAbs().maxCoeff()));
    EXPECT_LE(std::abs(w.res.objective - c.res.objective), 1e-10 * (1.0 + std::abs(c.res.objective)));
    expect_kkt(qp, w);
    warm_iterations += w.res.iterations;
    cold_iterations += c.res.iterations;
  }
  std::cout << "iterations: warm " << warm_iterations << ", cold " << cold_iterations << "\n";
  EXPECT_LT(warm_iterations, cold_iterations);
}

TEST(DenseQp, DeterministicAcrossSolverInstances) {
  std::mt19937 rng(5);
  const Qp qp = random_feasible(rng, 12, 3, 16, true);
  DenseQpSolver a = make_solver(12, 3, 16), b = make_solver(30, 10, 60);
  const Solution sa = solve(a, qp), sb = solve(b, qp);
  EXPECT_EQ(sa.x, sb.x);  // bit-identical, whatever the workspace capacity
  EXPECT_EQ(sa.res.iterations, sb.res.iterations);
  EXPECT_EQ(sa.res.objective, sb.res.objective);
}

TEST(DenseQp, SolveNeverAllocates) {
  const unsigned seed = 31337;
  std::cout << "seed " << seed << "\n";
  std::mt19937 rng(seed);
  DenseQpSolver warm = make_solver(20, 6, 40), cold;
  QpSettings cold_settings;
  cold_settings.warm_start = false;
  std::string why;
  ASSERT_EQ(DenseQpSolver::configure(20, 6, 40, cold_settings, &cold, &why), Status::kOk);
  // Problems of varying sizes, some infeasible, some with bad data; all built before counting.
  std::vector<Qp> problems;
  const int shapes[][3] = {{3, 0, 2}, {12, 6, 16}, {20, 0, 40}, {7, 3, 0}, {20, 6, 40}};
  for (const auto& shape : shapes)
    for (int k = 0; k < 8; ++k) problems.push_back(random_feasible(rng, shape[0], shape[1], shape[2], k % 2));
  Qp infeasible = random_feasible(rng, 12, 2, 16, true);
  infeasible.C.row(3) = -infeasible.C.row(2);
  infeasible.d[3] = -infeasible.d[2] - 1.0;
  problems.push_back(infeasible);
  Eigen::VectorXd x0;
  Qp fixed = random_feasible(rng, 12, 2, 16, true, &x0);  // variables eliminated (lb == ub)
  fixed.lb.head(4) = fixed.ub.head(4) = x0.head(4);
  problems.push_back(fixed);
  Qp all_fixed = random_feasible(rng, 5, 0, 3, true, &x0);
  all_fixed.lb = all_fixed.ub = x0;
  problems.push_back(all_fixed);
  Qp nan_data = random_feasible(rng, 12, 2, 16, false);
  nan_data.C(4, 4) = std::nan("");
  problems.push_back(nan_data);
  Eigen::VectorXd x_buf(20);
  const Eigen::MatrixXd big_H = Eigen::MatrixXd::Identity(20, 20);
  const Eigen::VectorXd big_g = Eigen::VectorXd::Ones(20), none;
  const Eigen::MatrixXd no_rows(0, 20);

  int optimal = 0, infeasible_count = 0, bad = 0;
  testing::AllocationScope scope;
  for (int k = 0; k < 4000; ++k) {
    const Qp& qp = problems[k % problems.size()];
    const int n = static_cast<int>(qp.H.rows());
    DenseQpSolver& solver = (k / 7) % 2 ? warm : cold;
    const QpResult r = solver.solve(qp.H, qp.g, qp.A, qp.b, qp.C, qp.d, qp.lb, qp.ub, x_buf.head(n));
    // A sub-block of a larger matrix works too (outer stride != rows).
    const QpResult r2 = solver.solve(big_H.topLeftCorner(n, n), big_g.head(n), no_rows.leftCols(n),
                                     none, no_rows.leftCols(n), none, none, none, x_buf.head(n));
    optimal += (r.status == QpStatus::kOptimal) + (r2.status == QpStatus::kOptimal);
    infeasible_count += r.status == QpStatus::kInfeasible;
    bad += r.status == QpStatus::kBadInput;
    (void)warm.eq_multipliers();
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_GT(optimal, 7000);
  EXPECT_GT(infeasible_count, 0);
  EXPECT_GT(bad, 0);
}

}  // namespace
}  // namespace kiloloop::qp
