#pragma once
// DenseQpSolver: dense, allocation-free convex QP solver for small problems at 1 kHz.
//
//   minimize    1/2 x' H x + g' x          H (n, n) symmetric positive definite
//   subject to  A_eq x  = b_eq             (n_eq rows)
//               C x    <= d                (n_ineq rows; d_i = +inf drops row i)
//               lb <= x <= ub              (optional; +-inf entries are ignored)
//
// Method: Goldfarb-Idnani dual active set (Math. Programming 27, 1983): start from the
// unconstrained minimum x = -H^-1 g, repeatedly add the most violated constraint (violation over
// row norm) with a step that keeps the active constraints satisfied and their multipliers >= 0,
// dropping an active inequality whose multiplier reaches 0 on the way. It keeps J = L^-T Q
// (H = L L', so J J' = H^-1) and the triangular R of the active normals: an addition is one
// Householder reflection of J's free columns, a drop a few Givens rotations. Equalities are
// added first and never dropped. Variables with lb == ub are eliminated before the factorization
// (H needs to be positive definite on the remaining ones only); their multipliers come from the
// KKT rows. Linearly dependent constraints (duplicated rows, a row repeating a bound, more
// equalities than variables) are recognized when they are added: an implied one is skipped, a
// contradicting one makes the problem infeasible.
//
// Warm start: before the most-violated loop, the inequalities and bounds that were active at the
// previous optimum (same sizes) are added in their previous order, each only if it is violated
// at the current iterate. Each is an ordinary dual step, so the optimum (unique: H is positive
// definite) does not change; only the number of iterations does.
//
// The workspace is sized once at configure() for the largest problem; solve() accepts any sizes
// up to those and never allocates, throws or reads a clock. Iterations are capped. The same data
// give bit-identical results whatever the workspace capacity.
//
// Multipliers (the last solve's problem sizes) satisfy the KKT conditions
//   H x + g + A_eq' lambda + C' mu + z = 0,   mu >= 0,   z_j = mu_ub_j - mu_lb_j,
// so mu_i > 0 only where row i is active and z_j > 0 (< 0) only where x_j sits on ub_j (lb_j).
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "kiloloop/status.hpp"

namespace kiloloop::qp {

enum class QpStatus : int {
  kOptimal = 0,
  kIterationLimit = 1,  // stopped at max_iterations; x is the last iterate (may violate constraints)
  kInfeasible = -1,     // the constraints admit no point
  kBadInput = -2,       // sizes beyond the workspace, non-finite data, data so large that its
                        // row sums overflow, H not symmetric positive definite (on the variables
                        // not fixed by lb == ub; entries below DBL_MIN count as 0)
  kNotConfigured = -3,
  kNumericalError = -4,  // the solve ended, but its x, objective or multipliers are not finite or
                         // x violates a constraint beyond the check tolerance (data at the edge of
                         // double range, extreme conditioning); x is a finite fallback
};

const char* to_string(QpStatus s) noexcept;

struct QpSettings {
  int max_iterations = 200;     // cap on active-set changes per solve
  // Violation accepted as satisfied, relative to the size of the terms of the constraint:
  // |b_i| + ||row_i||_1 ||x||_inf. A dependent constraint that cannot enter the active set is
  // declared infeasible only beyond 1000 times this.
  double feasibility_tol = 1e-12;
  bool warm_start = true;       // add the previous solve's active constraints first
};

struct QpResult {
  QpStatus status = QpStatus::kNotConfigured;
  int iterations = 0;     // active-set changes
  double objective = 0.0;  // 1/2 x'Hx + g'x at the returned x
  int n_active = 0;        // active inequality/bound constraints (fixed variables included)
};

class DenseQpSolver {
 public:
  using MatRef = Eigen::Ref<const Eigen::MatrixXd>;
  using VecRef = Eigen::Ref<const Eigen::VectorXd>;
  using VecView = Eigen::Map<const Eigen::VectorXd>;

  DenseQpSolver() = default;
  // Sizes the workspace for up to n variables, max_eq equalities, max_ineq inequalities (bounds
  // counted separately: up to 2 n of them).
  static Status configure(int n, int max_eq, int max_ineq, const QpSettings& settings,
                          DenseQpSolver* out, std::string* why);

  // Empty (0-row) A_eq/C and empty (size 0) lb/ub mean "none". x must have size n. H is read in
  // full and must be symmetric (to 1e-9 of its largest diagonal entry). d_i = +inf, lb_j = -inf,
  // ub_j = +inf are absent constraints; d_i = -inf, lb_j = +inf or ub_j = -inf can never be met
  // (kInfeasible, x zeroed); NaN anywhere and +-inf in H, g, A_eq, b_eq, C are kBadInput (x zeroed
  // when its size is right). On kInfeasible and kIterationLimit x holds the last iterate.
  //
  // The result is checked before it is returned: kOptimal only with a finite x, objective and
  // multipliers, and every constraint met to 1e4 x max(feasibility_tol, 1e-12) of the size of its
  // terms (|b_i| + ||row_i||_1 ||x||_inf). Otherwise kNumericalError. Whatever the status, x and
  // the multipliers are finite (a non-finite iterate is replaced by zeros).
  QpResult solve(const MatRef& H, const VecRef& g, const MatRef& A_eq, const VecRef& b_eq,
                 const MatRef& C, const VecRef& d, const VecRef& lb, const VecRef& ub,
                 Eigen::Ref<Eigen::VectorXd> x) noexcept;

  // Multipliers of the last solution (>= 0 for inequalities), sizes of the last problem; views
  // into the workspace, valid until the next solve.
  VecView eq_multipliers() const;     // (n_eq)   lambda
  VecView ineq_multipliers() const;   // (n_ineq) mu >= 0
  VecView bound_multipliers() const;  // (n)      z = mu_ub - mu_lb (0 when no bounds were given)
  void reset_warm_start() noexcept;  // forget the previous active set
  int max_variables() const { return n_max_; }
  int max_equalities() const { return me_max_; }
  int max_inequalities() const { return mi_max_; }
  const QpSettings& settings() const { return settings_; }

 private:
  struct Problem;  // raw views of one solve's data, defined in dense_qp.cpp
  enum class AddResult { kAdded, kSkipped, kInfeasible, kIterationLimit };

  // kOptimal when the data can be solved, else kBadInput or kInfeasible; fills the row norms.
  QpStatus check_values(const Problem& p) noexcept;
  template <int kN>
  QpStatus check_values_of(const Problem& p) noexcept;  // n = kN (0: p.n)
  Problem eliminate_fixed(const Problem& full) noexcept;
  bool factorize(const Problem& p) noexcept;
  double slack(const Problem& p, int c) const noexcept;  // n_c' x - b_c (>= form)
  double tolerance(const Problem& p, int c, double x_inf) const noexcept;
  double x_inf(int n) const noexcept;
  int most_violated(const Problem& p) noexcept;  // -1 when none
  template <int kN>
  int most_violated_of(const Problem& p) noexcept;  // n = kN (0: p.n)
  AddResult add_constraint(const Problem& p, int c) noexcept;
  void drop_active(int k, int n) noexcept;
  void finish(const Problem& full, const Problem& p, QpResult* res) noexcept;
  bool verified(const Problem& full) noexcept;  // the check above (s_ as scratch)
  template <int kN>
  bool verified_of(const Problem& full) noexcept;  // n = kN (0: full.n)
  void sanitize_result(const Problem& full, QpResult* res) noexcept;      // finite x, multipliers

  QpSettings settings_;
  int n_max_ = 0, me_max_ = 0, mi_max_ = 0;

  // Constraints are numbered c = [equalities | rows of C | lower bounds | upper bounds]; each is
  // handled in the ">=" form n_c' x >= b_c (rows of C and upper bounds flip sign, equalities take
  // the sign that makes them violated when added). When every variable has lb == ub, those are
  // equalities on the lower bounds (nothing is left to eliminate).
  // Matrices are column-major with leading dimension n_max (the first n rows/columns are used).
  Eigen::MatrixXd L_;  // (n, n) Cholesky factor of H, lower
  Eigen::MatrixXd J_;  // (n, n) J = L^-T Q: J J' = H^-1, J' N = [R; 0] for the active normals N
  Eigen::MatrixXd R_;  // (n, n) upper triangular, first q columns used
  Eigen::VectorXd x_, d_, z_, r_, np_, u_, tmp_;  // (n)
  Eigen::VectorXd s_;                              // (max_ineq) slacks d - C x
  Eigen::VectorXd norm1_, norm2_;                  // (max_eq + max_ineq) row norms of A_eq, C
  Eigen::VectorXd eq_mult_, ineq_mult_, bound_mult_;
  // Variables with lb == ub are eliminated: the algorithm runs on copies of the data restricted
  // to the free variables, with g, b_eq and d shifted by the fixed values.
  Eigen::MatrixXd Hr_, Ar_, Cr_;             // (n, n), (max_eq, n), (max_ineq, n)
  Eigen::VectorXd gr_, br_, dr_, lbr_, ubr_;  // (n), (max_eq), (max_ineq), (n), (n)
  Eigen::VectorXd xf_;                        // (n) solution in the full variables
  std::vector<int> free_, reduced_index_;     // (n) free variable of each reduced one; inverse
  double fixed_inf_ = 0.0;                    // largest |fixed value| (tolerance scale)
  std::vector<int> active_;              // (n) constraint numbers of the active set, in order
  // Per constraint (max_eq + max_ineq + 2 n): active (1), implied by a fixed variable (2; the
  // upper bound where lb == ub), handled as an equality (rows of A_eq, lower bounds where
  // lb == ub), and for those the sign of the >= form (+1: n_c = a_c, -1: n_c = -a_c).
  std::vector<signed char> is_active_, is_equality_, sign_;
  std::vector<std::int64_t> skipped_;    // (max_eq + max_ineq + 2 n) epoch a constraint was skipped
  std::int64_t epoch_ = 0;               // advances on every active-set change
  int q_ = 0, iterations_ = 0;

  // Warm start: inequality/bound constraints active at the previous optimum, in order added.
  std::vector<int> warm_;
  int warm_count_ = 0, warm_n_ = -1, warm_me_ = -1, warm_mi_ = -1;
  bool warm_lb_ = false, warm_ub_ = false;

  int last_n_ = 0, last_me_ = 0, last_mi_ = 0;  // sizes of the last problem (multiplier views)
};

}  // namespace kiloloop::qp
