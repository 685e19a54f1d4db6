// QP target: random feasible problems (built around a point x0, as tests/test_qp.py) of varying
// sizes in one reused workspace, with extreme, non-finite and wrong-size data mixed in. Checks:
// x, objective and multipliers always finite; a failure status for NaN/inf data or wrong sizes;
// OPTIMAL only with an x that meets every constraint (checked here in long double, to 1e-6 of
// the size of each constraint's terms - looser than the solver's own 1e-8, so only real lies
// count).
#include <cmath>
#include <limits>

#include "fuzz_common.hpp"
#include "kiloloop/qp/dense_qp.hpp"

namespace kiloloop::fuzz {
namespace {

constexpr int kN = 8, kMe = 3, kMi = 6;
constexpr double kInf = std::numeric_limits<double>::infinity();

struct Problem {
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(kN, kN), A = Eigen::MatrixXd::Zero(kMe, kN),
                  C = Eigen::MatrixXd::Zero(kMi, kN), M = Eigen::MatrixXd::Zero(kN, kN);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(kN), b = Eigen::VectorXd::Zero(kMe),
                  d = Eigen::VectorXd::Zero(kMi), lb = Eigen::VectorXd::Zero(kN),
                  ub = Eigen::VectorXd::Zero(kN), x0 = Eigen::VectorXd::Zero(kN),
                  x = Eigen::VectorXd::Zero(kN);
};

// Largest violation of the problem's constraints at x relative to the size of their terms; inf
// when a residual or its scale is not finite.
double violation(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::VectorXd>& b,
                 const Eigen::Ref<const Eigen::MatrixXd>& C, const Eigen::Ref<const Eigen::VectorXd>& d,
                 const Eigen::Ref<const Eigen::VectorXd>& lb, const Eigen::Ref<const Eigen::VectorXd>& ub,
                 const Eigen::Ref<const Eigen::VectorXd>& x) {
  const int n = static_cast<int>(x.size());
  long double xi = 0;
  for (int j = 0; j < n; ++j) xi = std::max<long double>(xi, std::fabs((long double)x[j]));
  double worst = 0.0;
  auto row = [&](const Eigen::Ref<const Eigen::MatrixXd>& M, int i, double rhs, bool eq) {
    long double r = 0, scale = std::fabs((long double)rhs);
    for (int j = 0; j < n; ++j) {
      r += (long double)M(i, j) * x[j];
      scale += std::fabs((long double)M(i, j)) * xi;
    }
    r -= rhs;
    if (eq) r = std::fabs(r);
    const long double v = r / std::max<long double>(scale, 1e-300L);
    if (!std::isfinite((double)v) || !std::isfinite((double)scale)) return kInf;
    return (double)std::max<long double>(v, 0);
  };
  for (int i = 0; i < A.rows(); ++i) worst = std::max(worst, row(A, i, b[i], true));
  for (int i = 0; i < C.rows(); ++i)
    if (d[i] != kInf) worst = std::max(worst, row(C, i, d[i], false));
  for (int j = 0; j < lb.size(); ++j)
    if (lb[j] != -kInf) {
      const long double s = std::fabs((long double)lb[j]) + xi;
      if (!std::isfinite((double)s)) return kInf;
      worst = std::max(worst, (double)(((long double)lb[j] - x[j]) / std::max<long double>(s, 1e-300L)));
    }
  for (int j = 0; j < ub.size(); ++j)
    if (ub[j] != kInf) {
      const long double s = std::fabs((long double)ub[j]) + xi;
      if (!std::isfinite((double)s)) return kInf;
      worst = std::max(worst, (double)(((long double)x[j] - ub[j]) / std::max<long double>(s, 1e-300L)));
    }
  return worst;
}

}  // namespace

Tally fuzz_qp(std::uint64_t seed, std::uint64_t inputs, volatile std::uint64_t* progress) {
  Tally tally;
  tally.target = "qp";
  Rng r(seed * 0x51ED2701ull + 1);
  qp::DenseQpSolver solver;
  std::string why;
  qp::DenseQpSolver::configure(kN, kMe, kMi, qp::QpSettings{}, &solver, &why);
  Problem p;
  Eigen::VectorXd x_wrong(kN + 1), none;
  const Eigen::MatrixXd Cbig = Eigen::MatrixXd::Ones(kMi + 1, kN);
  const Eigen::VectorXd dbig = Eigen::VectorXd::Ones(kMi + 1);
  Desc desc;
  std::uint64_t clean_not_optimal = 0;
  for (std::uint64_t k = 0; k < inputs; ++k) {
    *progress = k;
    ++tally.inputs;
    desc.clear();
    // A feasible problem of random size around x0.
    const int n = 1 + r.below(kN), me = r.below(std::min(kMe, n) + 1), mi = r.below(kMi + 1);
    const bool bounds = r.chance(0.5);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) p.M(i, j) = r.uniform(-1.0, 1.0);
    p.H.topLeftCorner(n, n) = p.M.topLeftCorner(n, n) * p.M.topLeftCorner(n, n).transpose() / n;
    p.H.topLeftCorner(n, n).diagonal().array() += 0.1;
    for (int j = 0; j < n; ++j) p.g[j] = r.uniform(-3.0, 3.0), p.x0[j] = r.uniform(-1.0, 1.0);
    for (int i = 0; i < me; ++i) {
      for (int j = 0; j < n; ++j) p.A(i, j) = r.uniform(-1.0, 1.0);
      p.b[i] = p.A.row(i).head(n).dot(p.x0.head(n));
    }
    for (int i = 0; i < mi; ++i) {
      for (int j = 0; j < n; ++j) p.C(i, j) = r.uniform(-1.0, 1.0);
      p.d[i] = p.C.row(i).head(n).dot(p.x0.head(n)) + (r.chance(0.3) ? 0.0 : r.uniform());
    }
    for (int j = 0; j < n; ++j) {
      p.lb[j] = r.chance(0.2) ? -kInf : p.x0[j] - (r.chance(0.2) ? 0.0 : r.uniform());
      p.ub[j] = r.chance(0.2) ? kInf : p.x0[j] + (r.chance(0.2) ? 0.0 : r.uniform());
    }
    // Mutations: none (40%), or 1-3 of: a non-finite entry, an extreme entry, a wrong size, an
    // indefinite / asymmetric / singular H.
    bool size_bad = false, structure_bad = false;
    int size_kind = -1, structure_kind = -1;
    const int mutations = r.chance(0.4) ? 0 : 1 + r.below(3);
    for (int m = 0; m < mutations; ++m) {
      const int what = r.below(10);
      const bool nonfinite = what < 4;
      if (what < 8) {
        switch (r.below(8)) {
          case 0: {  // H, kept symmetric
            const int i = r.below(n), j = r.below(n);
            p.H(i, j) = p.H(j, i) = nonfinite ? nonfinite_value(r) : extreme_value(r);
            desc.add("H(%d,%d)=H(%d,%d)=%.17g", i, j, j, i, p.H(i, j));
            break;
          }
          case 1: poke(r, p.g.data(), n, nonfinite, desc, "g"); break;
          case 2:
            if (me > 0) {
              const int i = r.below(me), j = r.below(n);
              p.A(i, j) = nonfinite ? nonfinite_value(r) : extreme_value(r);
              desc.add("A(%d,%d)=%.17g", i, j, p.A(i, j));
            }
            break;
          case 3: poke(r, p.b.data(), me, nonfinite, desc, "b"); break;
          case 4:
            if (mi > 0) {
              const int i = r.below(mi), j = r.below(n);
              p.C(i, j) = nonfinite ? nonfinite_value(r) : extreme_value(r);
              desc.add("C(%d,%d)=%.17g", i, j, p.C(i, j));
            }
            break;
          case 5: poke(r, p.d.data(), mi, nonfinite, desc, "d"); break;
          case 6: if (bounds) poke(r, p.lb.data(), n, nonfinite, desc, "lb"); break;
          default: if (bounds) poke(r, p.ub.data(), n, nonfinite, desc, "ub"); break;
        }
      } else if (what == 8) {
        size_kind = r.below(4);
        static const char* kSizeNames[] = {"x of size n+1", "C with max_ineq+1 rows",
                                           "g of size n-1", "d one longer than C"};
        desc.add("%s", kSizeNames[size_kind]);
        size_bad = true;
      } else {
        structure_kind = r.below(2);  // applied after the other mutations (which could undo it)
      }
    }
    if (structure_kind >= 0) {
      // A negative pivot on a variable that is not eliminated (lb == ub removes its row and
      // column unless every variable is fixed), or an asymmetry beyond the 1e-9 tolerance.
      int j = 0, fixed = 0;
      for (int i = 0; i < n; ++i) fixed += bounds && p.lb[i] == p.ub[i];
      while (j < n - 1 && fixed < n && bounds && p.lb[j] == p.ub[j]) ++j;
      if (structure_kind == 0 || n == 1) {
        p.H(j, j) = -1.0;
        desc.add("H(%d,%d)=-1 (indefinite)", j, j);
      } else {
        const double big = p.H.topLeftCorner(n, n).cwiseAbs().maxCoeff();
        p.H(0, 1) += 1.0 + 1e-6 * (std::isfinite(big) ? big : 0.0);
        desc.add("H(0,1)=%.17g (asymmetric)", p.H(0, 1));
      }
      structure_bad = true;
    }
    // Bad by the contract, from the data as it now is: NaN/inf in H, g, A, b, C; NaN or a never
    // met infinity in d, lb, ub (+inf in d, -inf in lb, +inf in ub are absent constraints).
    auto bound_bad = [&](const Eigen::VectorXd& v, int len, double absent) {
      for (int i = 0; i < len; ++i)
        if (!std::isfinite(v[i]) && v[i] != absent) return true;
      return false;
    };
    const bool bad = size_bad || structure_bad || !p.H.topLeftCorner(n, n).allFinite() ||
                     !p.g.head(n).allFinite() || !p.A.topLeftCorner(me, n).allFinite() ||
                     !p.b.head(me).allFinite() || !p.C.topLeftCorner(mi, n).allFinite() ||
                     bound_bad(p.d, mi, kInf) ||
                     (bounds && (bound_bad(p.lb, n, -kInf) || bound_bad(p.ub, n, kInf)));
    tally.bad_inputs += bad;

    using CRef = Eigen::Ref<const Eigen::VectorXd>;
    const CRef lbv = bounds ? CRef(p.lb.head(n)) : CRef(none);
    const CRef ubv = bounds ? CRef(p.ub.head(n)) : CRef(none);
    const bool wrong_x = size_kind == 0;
    Eigen::Ref<Eigen::VectorXd> x = wrong_x ? Eigen::Ref<Eigen::VectorXd>(x_wrong)
                                            : Eigen::Ref<Eigen::VectorXd>(p.x.head(n));
    qp::QpResult res;
    if (size_kind == 1) {
      res = solver.solve(p.H.topLeftCorner(n, n), p.g.head(n), p.A.topLeftCorner(me, n),
                         p.b.head(me), Cbig.topLeftCorner(kMi + 1, n), dbig, lbv, ubv, x);
    } else {
      const int gn = size_kind == 2 ? n - 1 : n;
      const int crows = size_kind == 3 && mi == kMi ? mi - 1 : mi;
      const int dn = size_kind == 3 ? crows + 1 : mi;
      res = solver.solve(p.H.topLeftCorner(n, n), p.g.head(gn), p.A.topLeftCorner(me, n),
                         p.b.head(me), p.C.topLeftCorner(crows, n), p.d.head(dn), lbv, ubv, x);
    }
    const bool sized = !wrong_x;
    if (sized && !x.allFinite()) tally.fail(k, desc, &tally.bad_outputs, "x not finite (status %s)", qp::to_string(res.status));
    if (!std::isfinite(res.objective)) tally.fail(k, desc, &tally.bad_outputs, "objective %g", res.objective);
    if (!solver.eq_multipliers().allFinite() || !solver.ineq_multipliers().allFinite() ||
        !solver.bound_multipliers().allFinite())
      tally.fail(k, desc, &tally.bad_outputs, "multipliers not finite");
    if (bad && static_cast<int>(res.status) >= 0)
      tally.fail(k, desc, &tally.missed_status, "bad input answered %s", qp::to_string(res.status));
    if (res.status == qp::QpStatus::kOptimal && sized) {
      const double v = violation(p.A.topLeftCorner(me, n), p.b.head(me), p.C.topLeftCorner(mi, n),
                                 p.d.head(mi), lbv, ubv, x);
      if (!(v <= 1e-6)) tally.fail(k, desc, &tally.bad_outputs, "OPTIMAL with violation %g", v);
    }
    if (mutations == 0 && res.status != qp::QpStatus::kOptimal) ++clean_not_optimal;
  }
  std::printf("  [qp] clean feasible problems not solved to OPTIMAL: %llu\n",
              static_cast<unsigned long long>(clean_not_optimal));
  return tally;
}

}  // namespace kiloloop::fuzz
