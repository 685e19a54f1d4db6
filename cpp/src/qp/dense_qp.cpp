#include "kiloloop/qp/dense_qp.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <type_traits>

namespace kiloloop::qp {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Complete unrolling of the loop that follows where its trip count is a compile-time constant
// (with_fixed_size's sizes).
#define KILOLOOP_UNROLL _Pragma("GCC unroll 16")

// f(std::integral_constant<int, n>()) at the stance-force QP's sizes (3 variables per stance
// leg; its full problem has 12), f(std::integral_constant<int, 0>()) (n at run time) otherwise:
// the loops of f over n unroll completely at those sizes (KILOLOOP_UNROLL).
template <class F>
decltype(auto) with_fixed_size(int n, F&& f) {
  switch (n) {
    case 3: return f(std::integral_constant<int, 3>());
    case 6: return f(std::integral_constant<int, 6>());
    case 9: return f(std::integral_constant<int, 9>());
    case 12: return f(std::integral_constant<int, 12>());
    default: return f(std::integral_constant<int, 0>());
  }
}

// A new normal is linearly dependent on the active ones when its component outside their span,
// measured in the H^-1 metric, is below this fraction of its length.
constexpr double kDependentTol = 1e-10;
// Cholesky pivots below this fraction of H's largest diagonal entry: H is not (numerically) PD.
constexpr double kPivotTol = 1e-13;
// H must be symmetric to this fraction of its largest diagonal entry.
constexpr double kSymmetryTol = 1e-9;
// A dependent constraint that cannot enter is skipped when violated by less than this many
// feasibility tolerances (rounding at a degenerate vertex), infeasible beyond.
constexpr double kDependentSlackFactor = 1e3;
// The result check accepts a constraint violated by up to this many feasibility tolerances
// (above kDependentSlackFactor: a skipped dependent constraint may use that much), with the
// tolerance floored at kCheckTolFloor so that feasibility_tol = 0 still leaves room for rounding.
constexpr double kCheckFactor = 1e4;
constexpr double kCheckTolFloor = 1e-12;

// Givens rotation (c, s) with [c s; -s c] [a; b] = [h; 0], h = |(a, b)| >= 0, overflow-safe.
inline double givens(double a, double b, double* c, double* s) {
  const double aa = std::abs(a), ab = std::abs(b);
  double h;
  if (aa >= ab) {
    const double t = b / a;
    h = aa * std::sqrt(1.0 + t * t);
  } else {
    const double t = a / b;
    h = ab * std::sqrt(1.0 + t * t);
  }
  *c = a / h;
  *s = b / h;
  return h;
}

// Plain loops over raw columns: at these sizes (n <= ~30) they beat Eigen's dynamic-size kernels,
// whose dispatch costs more than the arithmetic. Pairs of entries are written out so that the
// compiler's straight-line (SLP) vectorizer uses 2-wide SIMD even at -O2; the operations per entry
// are the same, so results do not depend on it.

// Columns a and b (length n, not overlapping) become (c a + s b, c b - s a).
inline void rotate(double* __restrict a, double* __restrict b, int n, double c, double s) {
  int i = 0;
  for (; i + 1 < n; i += 2) {
    const double a0 = a[i], a1 = a[i + 1], b0 = b[i], b1 = b[i + 1];
    a[i] = c * a0 + s * b0;
    a[i + 1] = c * a1 + s * b1;
    b[i] = c * b0 - s * a0;
    b[i + 1] = c * b1 - s * a1;
  }
  if (i < n) {
    const double a0 = a[i], b0 = b[i];
    a[i] = c * a0 + s * b0;
    b[i] = c * b0 - s * a0;
  }
}

// y += alpha x (not overlapping).
inline void axpy(double* __restrict y, const double* __restrict x, double alpha, int n) {
  int i = 0;
  for (; i + 1 < n; i += 2) {
    y[i] += alpha * x[i];
    y[i + 1] += alpha * x[i + 1];
  }
  if (i < n) y[i] += alpha * x[i];
}

// Two partial sums (even and odd entries), added at the end.
inline double dot(const double* a, const double* b, int n) {
  double s0 = 0.0, s1 = 0.0;
  int i = 0;
  for (; i + 1 < n; i += 2) {
    s0 += a[i] * b[i];
    s1 += a[i + 1] * b[i + 1];
  }
  if (i < n) s0 += a[i] * b[i];
  return s0 + s1;
}

// Row i of a column-major matrix (leading dimension ld) times x.
inline double row_dot(const double* M, int ld, int i, const double* x, int n) {
  double sum = 0.0;
  for (int j = 0; j < n; ++j) sum += M[i + j * ld] * x[j];
  return sum;
}

// out = y0 + C x (y0 null: from 0; kNegate: y0 - C x) for an (m, n) column-major C, each row's
// sum taken over the columns in order (j = 0, 1, ...) as `out = y0` followed by
// axpy(out, C(:, j), +-x[j], m) for each j: the same operations in the same order. Row by row,
// two rows at a time in registers, instead of column by column through memory, where each of
// the n axpy passes loaded and stored every entry of out again (callgrind, 1 s trot, n = 12,
// m = 24: most_violated_of 2.20k -> 1.65k, verified_of 2.13k -> 1.27k instructions a call).
// kN > 0: n = kN, fixed at compile time (with_fixed_size).
template <int kN, bool kNegate>
void row_sums_of_products(const double* y0, const double* C, int ld, int m, const double* x,
                          int n_runtime, double* __restrict out) {
  const int n = kN > 0 ? kN : n_runtime;
  int i = 0;
  for (; i + 1 < m; i += 2) {
    double s0 = y0 ? y0[i] : 0.0, s1 = y0 ? y0[i + 1] : 0.0;
    KILOLOOP_UNROLL for (int j = 0; j < n; ++j) {
      const double alpha = kNegate ? -x[j] : x[j];
      s0 += alpha * C[i + j * ld];
      s1 += alpha * C[i + 1 + j * ld];
    }
    out[i] = s0;
    out[i + 1] = s1;
  }
  if (i < m) {
    double s0 = y0 ? y0[i] : 0.0;
    KILOLOOP_UNROLL for (int j = 0; j < n; ++j) s0 += (kNegate ? -x[j] : x[j]) * C[i + j * ld];
    out[i] = s0;
  }
}

// Row norms (1 and 2) of an (m, n) column-major matrix; false if an entry is not finite or a
// 1-norm overflows. A 2-norm whose sum of squares overflows (entries beyond ~1e154) or underflows
// (all entries below ~1e-154) is recomputed scaled by the row's largest entry: the norm itself is
// representable, and a 0 or inf there would make a violated row look infinitely or not at all
// violated.
// kN > 0: n = kN, fixed at compile time (with_fixed_size).
template <int kN = 0>
bool row_norms(const double* M, int ld, int m, int n_runtime, double* norm1, double* norm2) {
  const int n = kN > 0 ? kN : n_runtime;
  // Each row's sums over the columns in order (j = 0, 1, ...), two rows at a time in registers
  // (2-wide SIMD at -O2, see rotate). Summed in place, norm1 and norm2 were stored and loaded
  // again for every entry: the compiler cannot rule out that they alias M.
  int i = 0;
  for (; i + 1 < m; i += 2) {
    double s1 = 0.0, t1 = 0.0, s2 = 0.0, t2 = 0.0;  // rows i, i + 1: 1-norm, sum of squares
    KILOLOOP_UNROLL for (int j = 0; j < n; ++j) {
      const double v0 = std::abs(M[i + j * ld]), v1 = std::abs(M[i + 1 + j * ld]);
      s1 += v0;
      t1 += v1;
      s2 += v0 * v0;
      t2 += v1 * v1;
    }
    norm1[i] = s1;
    norm1[i + 1] = t1;
    norm2[i] = s2;
    norm2[i + 1] = t2;
  }
  if (i < m) {
    double s1 = 0.0, s2 = 0.0;
    KILOLOOP_UNROLL for (int j = 0; j < n; ++j) {
      const double v = std::abs(M[i + j * ld]);
      s1 += v;
      s2 += v * v;
    }
    norm1[i] = s1;
    norm2[i] = s2;
  }
  for (int i = 0; i < m; ++i) {
    if (!std::isfinite(norm1[i])) return false;  // |NaN| and |inf| propagate into the sum
    if (norm2[i] >= DBL_MIN && norm2[i] <= DBL_MAX) {
      norm2[i] = std::sqrt(norm2[i]);
      continue;
    }
    double big = 0.0;
    for (int j = 0; j < n; ++j) big = std::max(big, std::abs(M[i + j * ld]));
    double sum = 0.0;
    if (big > 0.0)
      for (int j = 0; j < n; ++j) {
        const double v = M[i + j * ld] / big;
        sum += v * v;
      }
    norm2[i] = big * std::sqrt(sum);
  }
  return true;
}

template <int kN = 0>
bool all_finite(const double* v, int n_runtime) {
  const int n = kN > 0 ? kN : n_runtime;
  bool finite = true;
  KILOLOOP_UNROLL for (int i = 0; i < n; ++i) finite &= v[i] - v[i] == 0.0;  // false for NaN and inf
  return finite;
}

// Bounds: NaN is bad data; an infinity of the `absent` sign drops the bound, one of the other
// sign can never be met.
template <int kN = 0>
QpStatus check_bounds(const double* v, int n_runtime, double absent) {
  const int n = kN > 0 ? kN : n_runtime;
  KILOLOOP_UNROLL for (int i = 0; i < n; ++i) {
    if (std::isnan(v[i])) return QpStatus::kBadInput;
    if (std::isinf(v[i]) && v[i] != absent) return QpStatus::kInfeasible;
  }
  return QpStatus::kOptimal;
}

// |v| with entries below DBL_MIN (denormals) taken as 0: such a scale is numerically nothing.
inline double magnitude(double v) {
  const double a = std::abs(v);
  return a < DBL_MIN ? 0.0 : a;
}

}  // namespace

const char* to_string(QpStatus s) noexcept {
  switch (s) {
    case QpStatus::kOptimal: return "optimal";
    case QpStatus::kIterationLimit: return "iteration_limit";
    case QpStatus::kInfeasible: return "infeasible";
    case QpStatus::kBadInput: return "bad_input";
    case QpStatus::kNotConfigured: return "not_configured";
    case QpStatus::kNumericalError: return "numerical_error";
  }
  return "unknown";
}

// Raw column-major views of one solve's data; constraint numbers c run over
// [equalities | rows of C | lower bounds | upper bounds].
struct DenseQpSolver::Problem {
  const double* H;
  int ldh;
  const double* g;
  const double* A;
  int lda;
  const double* b;
  const double* C;
  int ldc;
  const double* d;
  const double* lb;  // null when there are no lower bounds
  const double* ub;  // null when there are no upper bounds
  int n, me, mi;
  int lb0() const { return me + mi; }
  int ub0() const { return me + mi + n; }
};

Status DenseQpSolver::configure(int n, int max_eq, int max_ineq, const QpSettings& settings,
                                DenseQpSolver* out, std::string* why) {
  auto fail = [&](const char* reason) {
    if (why) *why = reason;
    return Status::kInvalidConfig;
  };
  if (!out) return fail("out is null");
  if (n < 1) return fail("n must be >= 1");
  if (max_eq < 0 || max_ineq < 0) return fail("max_eq and max_ineq must be >= 0");
  if (settings.max_iterations < 1) return fail("max_iterations must be >= 1");
  if (!(settings.feasibility_tol >= 0.0) || !std::isfinite(settings.feasibility_tol))
    return fail("feasibility_tol must be finite and >= 0");

  DenseQpSolver s;
  s.settings_ = settings;
  s.n_max_ = n;
  s.me_max_ = max_eq;
  s.mi_max_ = max_ineq;
  s.L_ = Eigen::MatrixXd::Zero(n, n);
  s.J_ = Eigen::MatrixXd::Zero(n, n);
  s.R_ = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::VectorXd* v : {&s.x_, &s.d_, &s.z_, &s.r_, &s.np_, &s.u_, &s.tmp_, &s.bound_mult_,
                             &s.gr_, &s.lbr_, &s.ubr_, &s.xf_})
    *v = Eigen::VectorXd::Zero(n);
  s.Hr_ = Eigen::MatrixXd::Zero(n, n);
  s.Ar_ = Eigen::MatrixXd::Zero(max_eq, n);
  s.Cr_ = Eigen::MatrixXd::Zero(max_ineq, n);
  s.br_ = Eigen::VectorXd::Zero(max_eq);
  s.dr_ = Eigen::VectorXd::Zero(max_ineq);
  s.free_.assign(n, 0);
  s.reduced_index_.assign(n, 0);
  s.s_ = Eigen::VectorXd::Zero(max_ineq);
  s.norm1_ = Eigen::VectorXd::Zero(max_eq + max_ineq);
  s.norm2_ = Eigen::VectorXd::Zero(max_eq + max_ineq);
  s.eq_mult_ = Eigen::VectorXd::Zero(max_eq);
  s.ineq_mult_ = Eigen::VectorXd::Zero(max_ineq);
  const int total = max_eq + max_ineq + 2 * n;
  s.active_.assign(n, -1);
  s.is_active_.assign(total, 0);
  s.is_equality_.assign(total, 0);
  s.sign_.assign(total, 1);
  s.skipped_.assign(total, -1);
  s.warm_.assign(n, -1);
  *out = std::move(s);
  return Status::kOk;
}

DenseQpSolver::VecView DenseQpSolver::eq_multipliers() const {
  return VecView(eq_mult_.data(), last_me_);
}
DenseQpSolver::VecView DenseQpSolver::ineq_multipliers() const {
  return VecView(ineq_mult_.data(), last_mi_);
}
DenseQpSolver::VecView DenseQpSolver::bound_multipliers() const {
  return VecView(bound_mult_.data(), last_n_);
}

void DenseQpSolver::reset_warm_start() noexcept {
  warm_count_ = 0;
  warm_n_ = warm_me_ = warm_mi_ = -1;
}

// Finite H, g, A_eq, b_eq, C and row sums that do not overflow; H symmetric; d may hold +inf
// (absent) and -inf (never met), lb -inf / +inf and ub +inf / -inf likewise. Fills the row norms.
// At with_fixed_size's sizes its loops over the variables unroll (the same checks, in the same order).
QpStatus DenseQpSolver::check_values(const Problem& p) noexcept {
  return with_fixed_size(p.n, [&](auto size) { return check_values_of<decltype(size)::value>(p); });
}

template <int kN>
QpStatus DenseQpSolver::check_values_of(const Problem& p) noexcept {
  const int n = kN > 0 ? kN : p.n;
  // H finite: its diagonal here; an off-diagonal entry in the symmetry test below, whose
  // tolerance is finite once the diagonal is: an infinite or NaN entry makes the difference of
  // the pair infinite or NaN, which fails it (one pass over H instead of two).
  KILOLOOP_UNROLL for (int j = 0; j < n; ++j)
    if (!(p.H[j + j * p.ldh] - p.H[j + j * p.ldh] == 0.0)) return QpStatus::kBadInput;
  // H symmetric to a fraction of its largest diagonal entry, which bounds every entry of a
  // positive definite matrix.
  double max_diag = 0.0;
  KILOLOOP_UNROLL for (int j = 0; j < n; ++j) max_diag = std::max(max_diag, magnitude(p.H[j + j * p.ldh]));
  const double sym_tol = kSymmetryTol * max_diag;
  KILOLOOP_UNROLL for (int j = 0; j < n; ++j)
    KILOLOOP_UNROLL for (int i = j + 1; i < n; ++i)
      if (!(std::abs(p.H[i + j * p.ldh] - p.H[j + i * p.ldh]) <= sym_tol)) return QpStatus::kBadInput;
  if (!all_finite<kN>(p.g, n) || !all_finite(p.b, p.me)) return QpStatus::kBadInput;
  if (!row_norms<kN>(p.A, p.lda, p.me, n, norm1_.data(), norm2_.data())) return QpStatus::kBadInput;
  if (!row_norms<kN>(p.C, p.ldc, p.mi, n, norm1_.data() + p.me, norm2_.data() + p.me))
    return QpStatus::kBadInput;
  // NaN anywhere is bad data before an impossible bound is infeasible.
  const QpStatus sd = check_bounds(p.d, p.mi, kInf);
  const QpStatus sl = p.lb ? check_bounds<kN>(p.lb, n, -kInf) : QpStatus::kOptimal;
  const QpStatus su = p.ub ? check_bounds<kN>(p.ub, n, kInf) : QpStatus::kOptimal;
  if (sd == QpStatus::kBadInput || sl == QpStatus::kBadInput || su == QpStatus::kBadInput)
    return QpStatus::kBadInput;
  if (sd != QpStatus::kOptimal || sl != QpStatus::kOptimal || su != QpStatus::kOptimal)
    return QpStatus::kInfeasible;
  return QpStatus::kOptimal;
}

// The problem in the free variables (lb < ub): H restricted to them, g + H(free, fixed) x_fixed,
// b_eq - A(:, fixed) x_fixed, d - C(:, fixed) x_fixed, copied into the workspace.
DenseQpSolver::Problem DenseQpSolver::eliminate_fixed(const Problem& f) noexcept {
  const int n = f.n;
  int nr = 0;
  fixed_inf_ = 0.0;
  for (int j = 0; j < n; ++j) {
    if (f.lb[j] == f.ub[j]) {
      reduced_index_[j] = -1;
      fixed_inf_ = std::max(fixed_inf_, std::abs(f.lb[j]));
    } else {
      reduced_index_[j] = nr;
      free_[nr++] = j;
    }
  }
  const int ld = n_max_, lda = me_max_, ldc = mi_max_;
  double *H = Hr_.data(), *g = gr_.data(), *A = Ar_.data(), *b = br_.data();
  double *C = Cr_.data(), *d = dr_.data(), *lb = lbr_.data(), *ub = ubr_.data();
  for (int k = 0; k < f.me; ++k) b[k] = f.b[k];
  for (int k = 0; k < f.mi; ++k) d[k] = f.d[k];
  for (int a = 0; a < nr; ++a) g[a] = f.g[free_[a]];
  for (int j = 0; j < n; ++j) {
    const double* hj = f.H + j * f.ldh;  // column j of H = row j (H is symmetric)
    const double* aj = f.A + j * f.lda;
    const double* cj = f.C + j * f.ldc;
    const int r = reduced_index_[j];
    if (r >= 0) {
      double* hr = H + r * ld;
      for (int a = 0; a < nr; ++a) hr[a] = hj[free_[a]];
      for (int k = 0; k < f.me; ++k) A[k + r * lda] = aj[k];
      for (int k = 0; k < f.mi; ++k) C[k + r * ldc] = cj[k];
      lb[r] = f.lb[j];
      ub[r] = f.ub[j];
    } else {
      const double xj = f.lb[j];
      for (int a = 0; a < nr; ++a) g[a] += hj[free_[a]] * xj;
      axpy(b, aj, -xj, f.me);
      axpy(d, cj, -xj, f.mi);  // +inf stays +inf
    }
  }
  return Problem{H, ld, g, A, lda, b, C, ldc, d, lb, ub, nr, f.me, f.mi};
}

namespace {

// H = L L' (left-looking, column by column), then J = L^-T, upper triangular, for n = kN (a
// compile-time size) or, with kN = 0, n = n_runtime. The fixed sizes are the stance-force QP's (3
// per stance leg): there GCC unrolls every loop below completely (the pragmas; at -O2 it unrolls
// none of them otherwise), the same operations in the same order without the loop and tail
// overhead that outweighs the arithmetic at these sizes (callgrind, alone: n = 12 7.1k -> 3.7k
// instructions, n = 6 1.7k -> 0.7k). Divisions are done once per diagonal entry: dividing inside
// the substitutions puts one on every step of a serial dependency chain.
template <int kN>
bool cholesky_inverse(const double* H, int ldh, int n_runtime, int ld, double* L, double* J,
                      double* w, double* inv_diag) noexcept {
  const int n = kN > 0 ? kN : n_runtime;
  // Diagonal entries below DBL_MIN count as 0 (a denormal H is numerically zero), and no pivot
  // may be below DBL_MIN: 1/sqrt of it would overflow J and x.
  double max_diag = 0.0;
  KILOLOOP_UNROLL for (int j = 0; j < n; ++j) max_diag = std::max(max_diag, H[j + j * ldh]);
  if (!(max_diag >= DBL_MIN)) return false;
  const double min_pivot = std::max(kPivotTol * max_diag, DBL_MIN);
  KILOLOOP_UNROLL for (int j = 0; j < n; ++j) {
    // w = H(j:n, j) - L(j:n, 0:j) L(j, 0:j)'
    KILOLOOP_UNROLL for (int i = j; i < n; ++i) w[i] = H[i + j * ldh];
    KILOLOOP_UNROLL for (int k = 0; k < j; ++k) axpy(w + j, L + k * ld + j, -L[j + k * ld], n - j);
    if (!(w[j] > min_pivot)) return false;
    const double ljj = std::sqrt(w[j]);
    const double inv = 1.0 / ljj;
    inv_diag[j] = inv;
    double* lj = L + j * ld;
    lj[j] = ljj;
    KILOLOOP_UNROLL for (int i = j + 1; i < n; ++i) lj[i] = w[i] * inv;
  }
  // J = L^-T from J' L = I: J(i, k) = -(sum_{l=i+1..k} J(l, k) L(l, i)) / L(i, i), row by row from
  // the bottom. The dot products of one row are independent of each other (they read rows
  // finished before), which keeps the pipeline full; column by column they would form one long
  // dependency chain.
  KILOLOOP_UNROLL for (int k = 0; k < n; ++k) {
    double* jk = J + k * ld;
    jk[k] = inv_diag[k];
    KILOLOOP_UNROLL for (int i = k + 1; i < n; ++i) jk[i] = 0.0;
  }
  KILOLOOP_UNROLL for (int i = n - 2; i >= 0; --i) {
    const double* li = L + i * ld;
    KILOLOOP_UNROLL for (int k = i + 1; k < n; ++k) {
      const double* jk = J + k * ld;
      J[i + k * ld] = -dot(jk + i + 1, li + i + 1, k - i) * inv_diag[i];
    }
  }
  return true;
}

// The objective x' H x / 2 + g' x (n = kN, 0: n_runtime), H x left in hx.
template <int kN>
double objective_of(const double* H, int ldh, const double* g, const double* x, int n_runtime,
                    double* hx) noexcept {
  const int n = kN > 0 ? kN : n_runtime;
  row_sums_of_products<kN, false>(nullptr, H, ldh, n, x, n, hx);
  return 0.5 * dot(x, hx, n) + dot(g, x, n);
}

// The unconstrained minimum x = -H^-1 g = -J J' g (J upper triangular), t = J' g as scratch.
template <int kN>
void unconstrained_minimum_of(const double* J, int ld, const double* g, int n_runtime, double* t,
                              double* x) noexcept {
  const int n = kN > 0 ? kN : n_runtime;
  KILOLOOP_UNROLL for (int k = 0; k < n; ++k) t[k] = dot(J + k * ld, g, k + 1);
  // x = -J t row by row, each row's sum over k = i, i + 1, ... in order from 0, in a register: the
  // same operations as an axpy per column k (rows 0..k) through memory (bit-identical on 900k
  // random cases with infinities, NaN and signed zeros).
  KILOLOOP_UNROLL for (int i = 0; i < n; ++i) {
    double sum = 0.0;
    KILOLOOP_UNROLL for (int k = i; k < n; ++k) sum += -t[k] * J[i + k * ld];
    x[i] = sum;
  }
}

double objective(const double* H, int ldh, const double* g, const double* x, int n, double* hx) noexcept {
  return with_fixed_size(n, [&](auto size) {
    return objective_of<decltype(size)::value>(H, ldh, g, x, n, hx);
  });
}

}  // namespace

bool DenseQpSolver::factorize(const Problem& p) noexcept {
  double* inv_diag = z_.data();  // scratch until the first constraint is added
  return with_fixed_size(p.n, [&](auto size) {
    return cholesky_inverse<decltype(size)::value>(p.H, p.ldh, p.n, n_max_, L_.data(), J_.data(),
                                                   tmp_.data(), inv_diag);
  });
}

double DenseQpSolver::x_inf(int n) const noexcept {
  double m = fixed_inf_;
  for (int i = 0; i < n; ++i) m = std::max(m, std::abs(x_[i]));
  return m;
}

double DenseQpSolver::slack(const Problem& p, int c) const noexcept {
  const double* x = x_.data();
  if (c < p.me) return sign_[c] * (row_dot(p.A, p.lda, c, x, p.n) - p.b[c]);
  if (c < p.lb0()) return p.d[c - p.me] - row_dot(p.C, p.ldc, c - p.me, x, p.n);
  if (c < p.ub0()) return p.lb ? sign_[c] * (x[c - p.lb0()] - p.lb[c - p.lb0()]) : kInf;
  return p.ub ? p.ub[c - p.ub0()] - x[c - p.ub0()] : kInf;
}

// Rounding in n_c' x - b_c is proportional to the size of its terms; x carries rounding of the
// order of eps ||x|| in every component (bounds included).
double DenseQpSolver::tolerance(const Problem& p, int c, double x_inf) const noexcept {
  const double tol = settings_.feasibility_tol;
  if (c < p.me) return tol * (std::abs(p.b[c]) + norm1_[c] * x_inf);
  if (c < p.lb0()) return tol * (std::abs(p.d[c - p.me]) + norm1_[c] * x_inf);
  if (c < p.ub0()) return tol * (std::abs(p.lb[c - p.lb0()]) + x_inf);
  return tol * (std::abs(p.ub[c - p.ub0()]) + x_inf);
}

// The inactive inequality or bound with the largest violation, measured as a distance in x
// (violation / row norm); ties go to the lowest number, so the choice is deterministic.
int DenseQpSolver::most_violated(const Problem& p) noexcept {
  return with_fixed_size(p.n, [&](auto size) { return most_violated_of<decltype(size)::value>(p); });
}

template <int kN>
int DenseQpSolver::most_violated_of(const Problem& p) noexcept {
  const int n = kN > 0 ? kN : p.n;
  const double* x = x_.data();
  const double xi = x_inf(n), tol = settings_.feasibility_tol;
  int best = -1;
  double best_v = 0.0;
  if (p.mi > 0) {
    double* s = s_.data();
    row_sums_of_products<kN, true>(p.d, p.C, p.ldc, p.mi, x, n, s);  // s = d - C x
    for (int i = 0; i < p.mi; ++i) {
      const int c = p.me + i;
      if (is_active_[c] || skipped_[c] == epoch_) continue;
      if (s[i] < -tol * (std::abs(p.d[i]) + norm1_[c] * xi)) {
        const double v = -s[i] / norm2_[c];
        if (v > best_v) best_v = v, best = c;
      }
    }
  }
  if (p.lb) {
    KILOLOOP_UNROLL for (int j = 0; j < n; ++j) {
      const int c = p.lb0() + j;
      const double sj = x[j] - p.lb[j];
      if (sj < -tol * (std::abs(p.lb[j]) + xi) && -sj > best_v && !is_active_[c] &&
          skipped_[c] != epoch_)
        best_v = -sj, best = c;
    }
  }
  if (p.ub) {
    KILOLOOP_UNROLL for (int j = 0; j < n; ++j) {
      const int c = p.ub0() + j;
      const double sj = p.ub[j] - x[j];
      if (sj < -tol * (std::abs(p.ub[j]) + xi) && -sj > best_v && !is_active_[c] &&
          skipped_[c] != epoch_)
        best_v = -sj, best = c;
    }
  }
  return best;
}

// Removes active constraint k: R loses column k and is made upper triangular again by Givens
// rotations of its rows, applied to the columns of J too (J' N = [R; 0] is kept).
void DenseQpSolver::drop_active(int k, int n) noexcept {
  const int ld = n_max_;
  double* R = R_.data();
  double* J = J_.data();
  is_active_[active_[k]] = 0;
  for (int i = k; i < q_ - 1; ++i) {
    active_[i] = active_[i + 1];
    u_[i] = u_[i + 1];
    for (int l = 0; l <= i + 1; ++l) R[l + i * ld] = R[l + (i + 1) * ld];
  }
  --q_;
  for (int i = k; i < q_; ++i) {
    const double b = R[i + 1 + i * ld];
    if (b == 0.0) continue;
    double c, s;
    R[i + i * ld] = givens(R[i + i * ld], b, &c, &s);
    R[i + 1 + i * ld] = 0.0;
    for (int l = i + 1; l < q_; ++l) {
      const double t1 = R[i + l * ld], t2 = R[i + 1 + l * ld];
      R[i + l * ld] = c * t1 + s * t2;
      R[i + 1 + l * ld] = c * t2 - s * t1;
    }
    rotate(J + i * ld, J + (i + 1) * ld, n, c, s);
  }
}

// One Goldfarb-Idnani "step 2" loop: moves x and the multipliers towards satisfying constraint c
// while keeping the active ones satisfied and their multipliers >= 0; drops active constraints
// whose multiplier reaches 0 on the way (partial steps) until c can be added (full step).
DenseQpSolver::AddResult DenseQpSolver::add_constraint(const Problem& p, int c) noexcept {
  const int n = p.n, ld = n_max_;
  double* J = J_.data();
  double* R = R_.data();
  double* d = d_.data();
  double* z = z_.data();
  double* r = r_.data();
  double* u = u_.data();
  double* x = x_.data();
  double* np = np_.data();
  const bool is_eq = is_equality_[c];
  // The normal n_c in >= form; equalities take the sign that makes them violated (s <= 0).
  if (is_eq) {
    sign_[c] = 1;
    sign_[c] = slack(p, c) > 0.0 ? -1 : 1;
  }
  if (c < p.me) {
    for (int j = 0; j < n; ++j) np[j] = sign_[c] * p.A[c + j * p.lda];
  } else if (c < p.lb0()) {
    for (int j = 0; j < n; ++j) np[j] = -p.C[c - p.me + j * p.ldc];
  }
  double u_new = 0.0;  // multiplier of c
  for (;;) {
    if (iterations_ >= settings_.max_iterations) return AddResult::kIterationLimit;
    // d = J' n_c: its first q entries give the dual direction, the rest the primal one.
    if (c < p.lb0()) {
      for (int k = 0; k < n; ++k) d[k] = dot(J + k * ld, np, n);
    } else {
      const int j = c < p.ub0() ? c - p.lb0() : c - p.ub0();
      const double sign = c < p.ub0() ? sign_[c] : -1.0;
      for (int k = 0; k < n; ++k) d[k] = sign * J[j + k * ld];
    }
    const int q = q_;
    double d1 = 0.0, d2 = 0.0;
    for (int k = 0; k < q; ++k) d1 += d[k] * d[k];
    for (int k = q; k < n; ++k) d2 += d[k] * d[k];
    const bool dependent = d2 <= kDependentTol * kDependentTol * (d1 + d2);

    // r = R^-1 d1: how the active multipliers change per unit of u_new. Partial step t1: the
    // largest step before an active inequality's multiplier reaches zero.
    double t1 = kInf;
    int k_drop = -1;
    if (q > 0) {
      for (int k = 0; k < q; ++k) r[k] = d[k];
      for (int k = q - 1; k >= 0; --k) {
        const double* rk = R + k * ld;
        const double v = r[k] / rk[k];
        r[k] = v;
        for (int i = 0; i < k; ++i) r[i] -= rk[i] * v;
      }
      for (int k = 0; k < q; ++k) {
        if (is_equality_[active_[k]] || !(r[k] > 0.0)) continue;
        const double t = u[k] / r[k];
        if (t < t1) t1 = t, k_drop = k;
      }
    }
    // Full step t2: the step that makes c active along z = J2 d2 (z' n_c = |d2|^2).
    const double s = slack(p, c);
    double t2 = kInf;
    if (!dependent) {
      for (int i = 0; i < n; ++i) z[i] = 0.0;
      for (int k = q; k < n; ++k) axpy(z, J + k * ld, d[k], n);
      t2 = std::max(0.0, -s / d2);
    }

    if (t1 == kInf && t2 == kInf) {
      // n_c is a combination of active normals that cannot be relaxed: c is implied by them
      // (skip it) or contradicts them (infeasible).
      const double tol = kDependentSlackFactor * tolerance(p, c, x_inf(n));
      if (is_eq ? std::abs(s) <= tol : s >= -tol) {
        skipped_[c] = epoch_;
        return AddResult::kSkipped;
      }
      return AddResult::kInfeasible;
    }

    const double t = std::min(t1, t2);
    if (t2 != kInf) axpy(x, z, t, n);
    for (int k = 0; k < q; ++k) u[k] -= t * r[k];
    u_new += t;
    ++iterations_;
    ++epoch_;
    if (t2 <= t1) {
      // Full step: c joins the active set. A Householder reflection P of J's last n - q columns
      // maps d2 onto -sigma e_1 (J2 <- J2 P keeps J' N = [R; 0]); R gains column q. Unlike a
      // sweep of Givens rotations it has no serial chain of square roots and divisions.
      const int m = n - q;
      if (m > 1) {
        const double alpha = std::sqrt(d2);
        const double sigma = d[q] >= 0.0 ? alpha : -alpha;  // no cancellation in v_0
        double* v = z;  // z is no longer needed
        for (int k = 0; k < m; ++k) v[k] = d[q + k];
        v[0] += sigma;
        const double beta = 1.0 / (sigma * v[0]);  // 2 / v'v
        double* w = tmp_.data();
        for (int i = 0; i < n; ++i) w[i] = 0.0;
        for (int k = 0; k < m; ++k) axpy(w, J + (q + k) * ld, v[k], n);  // w = J2 v
        for (int k = 0; k < m; ++k) axpy(J + (q + k) * ld, w, -beta * v[k], n);
        d[q] = -sigma;
      }
      for (int k = 0; k <= q; ++k) R[k + q * ld] = d[k];
      active_[q] = c;
      u[q] = u_new;
      is_active_[c] = 1;
      ++q_;
      return AddResult::kAdded;
    }
    // Partial (or purely dual) step: the blocking constraint leaves the active set; try again.
    u[k_drop] = 0.0;
    drop_active(k_drop, n);
  }
}

// Objective, multipliers (mapped back to the full problem) and the warm-start memory; the full
// solution goes to xf_.
void DenseQpSolver::finish(const Problem& full, const Problem& p, QpResult* res) noexcept {
  const int n = full.n;
  const bool reduced = p.n < n;
  double* x = xf_.data();
  for (int j = 0; j < n; ++j) x[j] = !reduced ? x_[j] : reduced_index_[j] < 0 ? full.lb[j] : x_[reduced_index_[j]];
  double* hx = tmp_.data();
  res->objective = objective(full.H, full.ldh, full.g, x, n, hx);
  res->iterations = iterations_;
  // Map the >= form multipliers u onto H x + g + A' lambda + C' mu + z = 0.
  eq_mult_.head(p.me).setZero();
  ineq_mult_.head(p.mi).setZero();
  bound_mult_.head(n).setZero();
  int n_active = 0;
  for (int k = 0; k < q_; ++k) {
    const int c = active_[k];
    if (c < p.me) {
      eq_mult_[c] = -sign_[c] * u_[k];
      continue;
    }
    ++n_active;
    if (is_equality_[c]) {  // lb == ub, not eliminated: the multiplier has either sign
      bound_mult_[c - p.lb0()] = -sign_[c] * u_[k];
      continue;
    }
    const double u = std::max(0.0, u_[k]);  // rounding may leave -1e-17 behind
    if (c < p.lb0()) ineq_mult_[c - p.me] = u;
    else if (c < p.ub0()) bound_mult_[free_[c - p.lb0()]] -= u;
    else bound_mult_[free_[c - p.ub0()]] += u;
  }
  if (reduced) {
    // An eliminated variable's multiplier balances its row of the KKT conditions.
    for (int j = 0; j < n; ++j) {
      if (reduced_index_[j] >= 0) continue;
      const double r = hx[j] + full.g[j] + dot(full.A + j * full.lda, eq_mult_.data(), full.me) +
                       dot(full.C + j * full.ldc, ineq_mult_.data(), full.mi);
      bound_mult_[j] = -r;
      ++n_active;
    }
  }
  res->n_active = n_active;
  last_n_ = n;
  last_me_ = p.me;
  last_mi_ = p.mi;
  // Remember the active inequalities of an optimum for the next solve's warm start, numbered in
  // the full problem (which variables are fixed may change from one solve to the next).
  warm_count_ = 0;
  if (res->status == QpStatus::kOptimal) {
    for (int k = 0; k < q_; ++k) {
      const int c = active_[k];
      if (is_equality_[c]) continue;
      warm_[warm_count_++] = c < p.lb0()   ? c
                             : c < p.ub0() ? full.lb0() + free_[c - p.lb0()]
                                           : full.ub0() + free_[c - p.ub0()];
    }
    warm_n_ = n;
    warm_me_ = p.me;
    warm_mi_ = p.mi;
    warm_lb_ = full.lb != nullptr;
    warm_ub_ = full.ub != nullptr;
  } else {
    reset_warm_start();
  }
}

QpResult DenseQpSolver::solve(const MatRef& H, const VecRef& g, const MatRef& A_eq,
                              const VecRef& b_eq, const MatRef& C, const VecRef& d,
                              const VecRef& lb, const VecRef& ub,
                              Eigen::Ref<Eigen::VectorXd> x) noexcept {
  QpResult res;
  if (n_max_ == 0) return res;  // kNotConfigured
  const int n = static_cast<int>(H.rows());
  const int me = static_cast<int>(A_eq.rows()), mi = static_cast<int>(C.rows());
  // Rejected before the solve: x zeroed (when its size is right), no multipliers.
  auto reject = [&](QpStatus status) {
    if (x.size() == H.rows()) x.setZero();
    last_n_ = last_me_ = last_mi_ = 0;
    reset_warm_start();
    res.status = status;
    return res;
  };
  auto bad_input = [&]() { return reject(QpStatus::kBadInput); };
  // Sizes against the workspace and each other.
  if (n < 1 || n > n_max_ || H.cols() != n || g.size() != n || x.size() != n) return bad_input();
  if (me > me_max_ || (me > 0 && A_eq.cols() != n) || b_eq.size() != me) return bad_input();
  if (mi > mi_max_ || (mi > 0 && C.cols() != n) || d.size() != mi) return bad_input();
  if ((lb.size() != 0 && lb.size() != n) || (ub.size() != 0 && ub.size() != n)) return bad_input();
  const Problem full{H.data(),   static_cast<int>(H.outerStride()),
                     g.data(),   A_eq.data(),
                     static_cast<int>(A_eq.outerStride()),
                     b_eq.data(), C.data(),
                     static_cast<int>(C.outerStride()),
                     d.data(),   lb.size() == n ? lb.data() : nullptr,
                     ub.size() == n ? ub.data() : nullptr,
                     n,          me,
                     mi};
  if (const QpStatus v = check_values(full); v != QpStatus::kOptimal) return reject(v);
  // Fixed variables (lb == ub) are eliminated unless all are fixed; then they are equalities.
  int n_fixed = 0;
  if (full.lb && full.ub)
    for (int j = 0; j < n; ++j) n_fixed += full.lb[j] == full.ub[j];
  fixed_inf_ = 0.0;
  const Problem p = n_fixed > 0 && n_fixed < n ? eliminate_fixed(full) : full;
  if (!factorize(p)) return bad_input();
  if (p.n == n) {
    for (int j = 0; j < n; ++j) free_[j] = reduced_index_[j] = j;
  }

  const int total = me + mi + 2 * p.n;
  std::fill(is_active_.begin(), is_active_.begin() + total, static_cast<signed char>(0));
  std::fill(is_equality_.begin(), is_equality_.begin() + total, static_cast<signed char>(0));
  std::fill(sign_.begin(), sign_.begin() + total, static_cast<signed char>(1));
  std::fill(is_equality_.begin(), is_equality_.begin() + me, static_cast<signed char>(1));
  if (n_fixed == n) {  // every variable fixed: equalities on the lower bounds
    for (int j = 0; j < n; ++j) {
      is_equality_[p.lb0() + j] = 1;
      is_active_[p.ub0() + j] = 2;  // implied by it: never a candidate
    }
  }
  q_ = 0;
  iterations_ = 0;
  ++epoch_;

  with_fixed_size(p.n, [&](auto size) {
    unconstrained_minimum_of<decltype(size)::value>(J_.data(), n_max_, p.g, p.n, tmp_.data(), x_.data());
  });

  auto stop = [&](AddResult r) {
    res.status = r == AddResult::kInfeasible ? QpStatus::kInfeasible : QpStatus::kIterationLimit;
    finish(full, p, &res);
    sanitize_result(full, &res);
    x = xf_.head(n);
    return res;
  };
  // Equalities first, in order (never dropped afterwards): rows of A_eq, then fixed variables.
  // Dependent consistent ones are skipped.
  for (int c = 0; c < me + (n_fixed == n ? n : 0); ++c) {
    const int cc = c < me ? c : p.lb0() + c - me;
    if (!is_equality_[cc]) continue;
    const AddResult r = add_constraint(p, cc);
    if (r == AddResult::kInfeasible || r == AddResult::kIterationLimit) return stop(r);
  }
  // Warm start: the previous optimum's active inequalities, in the order they were added, each
  // if it is violated at the current iterate. Every addition is an ordinary dual step (the
  // multipliers stay >= 0 and may drop others), so the optimum is the same as from a cold start;
  // only the path to it changes.
  if (settings_.warm_start && warm_n_ == n && warm_me_ == me && warm_mi_ == mi &&
      warm_lb_ == (p.lb != nullptr) && warm_ub_ == (p.ub != nullptr)) {
    for (int w = 0; w < warm_count_; ++w) {
      // Full numbering -> this problem's (a bound of a now fixed variable is skipped).
      int c = warm_[w];
      if (c >= full.lb0()) {
        const bool lower = c < full.ub0();
        const int r = reduced_index_[c - (lower ? full.lb0() : full.ub0())];
        if (r < 0) continue;
        c = (lower ? p.lb0() : p.ub0()) + r;
      }
      if (is_active_[c] || !(slack(p, c) < -tolerance(p, c, x_inf(p.n)))) continue;
      const AddResult r = add_constraint(p, c);
      if (r == AddResult::kInfeasible || r == AddResult::kIterationLimit) return stop(r);
    }
  }
  // Then the most violated constraint until none is.
  for (int c = most_violated(p); c >= 0; c = most_violated(p)) {
    const AddResult r = add_constraint(p, c);
    if (r == AddResult::kInfeasible || r == AddResult::kIterationLimit) return stop(r);
  }
  res.status = QpStatus::kOptimal;
  finish(full, p, &res);
  sanitize_result(full, &res);
  x = xf_.head(n);
  return res;
}

// The solver never claims more than it delivered: an optimum must pass verified(); any result
// has a finite x (zeros replace a non-finite iterate), objective and multipliers.
void DenseQpSolver::sanitize_result(const Problem& full, QpResult* res) noexcept {
  const int n = full.n;
  const bool x_finite = all_finite(xf_.data(), n);
  const bool mult_finite = all_finite(eq_mult_.data(), last_me_) &&
                           all_finite(ineq_mult_.data(), last_mi_) &&
                           all_finite(bound_mult_.data(), last_n_);
  const bool finite = x_finite && mult_finite && std::isfinite(res->objective);
  if (res->status == QpStatus::kOptimal && finite && verified(full)) return;
  if (res->status == QpStatus::kOptimal || !finite) {
    res->status = QpStatus::kNumericalError;
    reset_warm_start();  // do not start the next solve from an active set that failed the check
  }
  if (!x_finite) xf_.head(n).setZero();
  if (!mult_finite) {
    eq_mult_.head(last_me_).setZero();
    ineq_mult_.head(last_mi_).setZero();
    bound_mult_.head(last_n_).setZero();
  }
  if (!std::isfinite(res->objective) || !x_finite) {
    // Objective of the x actually returned; 0 if even that overflows.
    const double f = objective(full.H, full.ldh, full.g, xf_.data(), n, tmp_.data());
    res->objective = std::isfinite(f) ? f : 0.0;
  }
}

// Every constraint of the full problem met at xf_ to kCheckFactor feasibility tolerances of the
// size of its terms; a tolerance or residual that is not finite fails.
bool DenseQpSolver::verified(const Problem& full) noexcept {
  return with_fixed_size(full.n, [&](auto size) { return verified_of<decltype(size)::value>(full); });
}

template <int kN>
bool DenseQpSolver::verified_of(const Problem& full) noexcept {
  const int n = kN > 0 ? kN : full.n;
  const double* x = xf_.data();
  const double tol = kCheckFactor * std::max(settings_.feasibility_tol, kCheckTolFloor);
  double xi = 0.0;
  KILOLOOP_UNROLL for (int j = 0; j < n; ++j) xi = std::max(xi, std::abs(x[j]));
  for (int i = 0; i < full.me; ++i) {
    const double r = std::abs(row_dot(full.A, full.lda, i, x, n) - full.b[i]);
    const double t = tol * (std::abs(full.b[i]) + norm1_[i] * xi);
    if (!(r <= t) || !std::isfinite(t)) return false;
  }
  // C x: each row's sum in the order row_dot takes it (j = 0, 1, ...).
  double* cx = s_.data();
  row_sums_of_products<kN, false>(nullptr, full.C, full.ldc, full.mi, x, n, cx);
  for (int i = 0; i < full.mi; ++i) {
    if (full.d[i] == kInf) continue;  // absent row
    const double r = cx[i] - full.d[i];
    const double t = tol * (std::abs(full.d[i]) + norm1_[full.me + i] * xi);
    if (!(r <= t) || !std::isfinite(t)) return false;
  }
  KILOLOOP_UNROLL for (int j = 0; j < n; ++j) {
    if (full.lb && full.lb[j] != -kInf) {
      const double t = tol * (std::abs(full.lb[j]) + xi);
      if (!(full.lb[j] - x[j] <= t) || !std::isfinite(t)) return false;
    }
    if (full.ub && full.ub[j] != kInf) {
      const double t = tol * (std::abs(full.ub[j]) + xi);
      if (!(x[j] - full.ub[j] <= t) || !std::isfinite(t)) return false;
    }
  }
  return true;
}

}  // namespace kiloloop::qp
