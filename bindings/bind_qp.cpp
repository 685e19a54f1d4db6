// kiloloop._core.qp: DenseQpSolver and a one-shot solve(). Python passes constraint matrices one
// row per constraint (numpy's C order); they are copied into column-major buffers sized once.
#include <chrono>
#include <optional>

#include "common.hpp"
#include "kiloloop/qp/dense_qp.hpp"

namespace kiloloop::py_glue {
namespace {

using qp::DenseQpSolver;
using qp::QpStatus;
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct PyQpResult {
  QpStatus status = QpStatus::kNotConfigured;
  Eigen::VectorXd x, eq_multipliers, ineq_multipliers, bound_multipliers;
  double objective = 0.0;
  int iterations = 0, n_active = 0;
};

// ValueError "name: expected shape (rows, cols)[ with <cap_name> <= cap]" (built only on error).
[[noreturn]] void shape_error(const char* name, const std::string& shape, const char* cap_name = "",
                              int cap = -1) {
  std::string msg = std::string(name) + ": expected shape " + shape;
  if (cap >= 0) msg += std::string(" with ") + cap_name + " <= " + std::to_string(cap);
  throw py::value_error(msg);
}

std::string dims(int rows) { return "(" + std::to_string(rows) + ",)"; }

// obj as a C-ordered float64 array; ValueError for a non-numeric dtype.
std::optional<Array> as_array(const py::object& obj, const char* name) {
  if (obj.is_none()) return std::nullopt;
  if (py::isinstance<Array>(obj)) return py::reinterpret_borrow<Array>(obj);  // float64, C order
  py::array a = py::array::ensure(obj);
  if (!a) throw py::value_error(std::string(name) + ": expected a float array");
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::value_error(std::string(name) + ": expected a real (float64) array, got dtype " +
                          py::str(a.dtype()).cast<std::string>());
  return Array::ensure(a);
}

// The problem arrays of one call, shape-checked against n and the solver's capacity.
struct Problem {
  std::optional<Array> H, g, A, b, C, d, lb, ub;
  int n = 0, me = 0, mi = 0;
};

// n_max = 0 and m_max < 0: no capacity limits.
Problem parse(const py::object& H, const py::object& g, const py::object& A_eq,
              const py::object& b_eq, const py::object& C, const py::object& d,
              const py::object& lb, const py::object& ub, int n_max, int me_max, int mi_max) {
  Problem p;
  p.H = as_array(H, "H");
  if (!p.H || p.H->ndim() != 2 || p.H->shape(0) != p.H->shape(1) || p.H->shape(0) < 1 ||
      (n_max > 0 && p.H->shape(0) > n_max))
    shape_error("H", "(n, n)", "n", n_max > 0 ? n_max : -1);
  p.n = static_cast<int>(p.H->shape(0));
  p.g = as_array(g, "g");
  if (!p.g || p.g->ndim() != 1 || p.g->shape(0) != p.n) shape_error("g", dims(p.n));
  // A matrix (m, n) and its right-hand side (m,): both or neither.
  auto pair = [&](const py::object& M, const py::object& v, const char* mname, const char* vname,
                  int m_max, std::optional<Array>* Mo, std::optional<Array>* vo) {
    *Mo = as_array(M, mname);
    *vo = as_array(v, vname);
    if (!*Mo && !*vo) return 0;
    if (!*Mo || (*Mo)->ndim() != 2 || (*Mo)->shape(1) != p.n ||
        (m_max >= 0 && (*Mo)->shape(0) > m_max))
      shape_error(mname, "(m, " + std::to_string(p.n) + ")", "m", m_max);
    const int m = static_cast<int>((*Mo)->shape(0));
    if (!*vo || (*vo)->ndim() != 1 || (*vo)->shape(0) != m) shape_error(vname, dims(m));
    return m;
  };
  p.me = pair(A_eq, b_eq, "A_eq", "b_eq", me_max, &p.A, &p.b);
  p.mi = pair(C, d, "C", "d", mi_max, &p.C, &p.d);
  p.lb = as_array(lb, "lb");
  if (p.lb && (p.lb->ndim() != 1 || p.lb->shape(0) != p.n)) shape_error("lb", dims(p.n));
  p.ub = as_array(ub, "ub");
  if (p.ub && (p.ub->ndim() != 1 || p.ub->shape(0) != p.n)) shape_error("ub", dims(p.n));
  return p;
}

// A DenseQpSolver with column-major buffers for its inputs (no allocation per solve in C++).
class PySolver {
 public:
  PySolver(int n, int max_eq, int max_ineq, int max_iterations, bool warm_start,
           double feasibility_tol) {
    qp::QpSettings settings;
    settings.max_iterations = max_iterations;
    settings.warm_start = warm_start;
    settings.feasibility_tol = feasibility_tol;
    std::string why;
    raise_if_failed(DenseQpSolver::configure(n, max_eq, max_ineq, settings, &solver_, &why), why);
    H_.setZero(n, n);
    A_.setZero(max_eq, n);
    C_.setZero(max_ineq, n);
    g_.setZero(n);
    b_.setZero(max_eq);
    d_.setZero(max_ineq);
    lb_.setZero(n);
    ub_.setZero(n);
    x_.setZero(n);
  }

  Problem parse_for_me(const py::object& H, const py::object& g, const py::object& A_eq,
                       const py::object& b_eq, const py::object& C, const py::object& d,
                       const py::object& lb, const py::object& ub) const {
    return parse(H, g, A_eq, b_eq, C, d, lb, ub, solver_.max_variables(), solver_.max_equalities(),
                 solver_.max_inequalities());
  }

  // Copies one parsed problem (within capacity) into the buffers.
  void load(const Problem& p) {
    const int n = p.n;
    H_.topLeftCorner(n, n) = Eigen::Map<const RowMajor>(p.H->data(), n, n);
    g_.head(n) = Eigen::Map<const Eigen::VectorXd>(p.g->data(), n);
    if (p.me > 0) {
      A_.topLeftCorner(p.me, n) = Eigen::Map<const RowMajor>(p.A->data(), p.me, n);
      b_.head(p.me) = Eigen::Map<const Eigen::VectorXd>(p.b->data(), p.me);
    }
    if (p.mi > 0) {
      C_.topLeftCorner(p.mi, n) = Eigen::Map<const RowMajor>(p.C->data(), p.mi, n);
      d_.head(p.mi) = Eigen::Map<const Eigen::VectorXd>(p.d->data(), p.mi);
    }
    if (p.lb) lb_.head(n) = Eigen::Map<const Eigen::VectorXd>(p.lb->data(), n);
    if (p.ub) ub_.head(n) = Eigen::Map<const Eigen::VectorXd>(p.ub->data(), n);
  }

  qp::QpResult run(const Problem& p) noexcept {
    const int n = p.n;
    return solver_.solve(H_.topLeftCorner(n, n), g_.head(n), A_.topLeftCorner(p.me, n),
                         b_.head(p.me), C_.topLeftCorner(p.mi, n), d_.head(p.mi),
                         lb_.head(p.lb ? n : 0), ub_.head(p.ub ? n : 0), x_.head(n));
  }

  PyQpResult solve(const py::object& H, const py::object& g, const py::object& A_eq,
                   const py::object& b_eq, const py::object& C, const py::object& d,
                   const py::object& lb, const py::object& ub) {
    return solve_parsed(parse_for_me(H, g, A_eq, b_eq, C, d, lb, ub));
  }

  PyQpResult solve_parsed(const Problem& p) {
    load(p);
    const qp::QpResult r = run(p);
    PyQpResult out;
    out.status = r.status;
    out.objective = r.objective;
    out.iterations = r.iterations;
    out.n_active = r.n_active;
    out.x = x_.head(p.n);
    out.eq_multipliers = solver_.eq_multipliers();
    out.ineq_multipliers = solver_.ineq_multipliers();
    out.bound_multipliers = solver_.bound_multipliers();
    return out;
  }

  DenseQpSolver& core() { return solver_; }

 private:
  DenseQpSolver solver_;
  Eigen::MatrixXd H_, A_, C_;
  Eigen::VectorXd g_, b_, d_, lb_, ub_, x_;
};

// A problem of any size and a solver sized for exactly it (one-shot use).
Problem parse_any(const py::object& H, const py::object& g, const py::object& A_eq,
                  const py::object& b_eq, const py::object& C, const py::object& d,
                  const py::object& lb, const py::object& ub) {
  return parse(H, g, A_eq, b_eq, C, d, lb, ub, 0, -1, -1);
}

}  // namespace

void bind_qp(py::module_& parent) {
  py::module_ m = parent.def_submodule(
      "qp", "Dense Goldfarb-Idnani QP: min 1/2 x'Hx + g'x, A_eq x = b_eq, C x <= d, lb <= x <= ub");

  py::enum_<QpStatus>(m, "QpStatus")
      .value("OPTIMAL", QpStatus::kOptimal)
      .value("ITERATION_LIMIT", QpStatus::kIterationLimit)
      .value("INFEASIBLE", QpStatus::kInfeasible)
      .value("BAD_INPUT", QpStatus::kBadInput)
      .value("NOT_CONFIGURED", QpStatus::kNotConfigured)
      .value("NUMERICAL_ERROR", QpStatus::kNumericalError);

  py::class_<PyQpResult>(m, "QpResult")
      .def_readonly("status", &PyQpResult::status)
      .def_readonly("x", &PyQpResult::x, "(n) solution (last iterate unless OPTIMAL)")
      .def_readonly("objective", &PyQpResult::objective, "1/2 x'Hx + g'x at x")
      .def_readonly("iterations", &PyQpResult::iterations, "active-set changes")
      .def_readonly("n_active", &PyQpResult::n_active, "active inequality and bound constraints")
      .def_readonly("eq_multipliers", &PyQpResult::eq_multipliers, "(m_eq) lambda")
      .def_readonly("ineq_multipliers", &PyQpResult::ineq_multipliers, "(m) mu >= 0")
      .def_readonly("bound_multipliers", &PyQpResult::bound_multipliers,
                    "(n) z = mu_ub - mu_lb; H x + g + A_eq' lambda + C' mu + z = 0")
      .def("__repr__", [](const PyQpResult& r) {
        return "QpResult(status=" + std::string(qp::to_string(r.status)) +
               ", objective=" + std::to_string(r.objective) +
               ", iterations=" + std::to_string(r.iterations) + ")";
      });

  py::class_<PySolver>(m, "DenseQpSolver",
                       "Workspace sized once for up to n variables, max_eq equalities and "
                       "max_ineq inequalities; warm-starts from the previous active set")
      .def(py::init<int, int, int, int, bool, double>(), py::arg("n"), py::arg("max_eq") = 0,
           py::arg("max_ineq") = 0, py::arg("max_iterations") = 200, py::arg("warm_start") = true,
           py::arg("feasibility_tol") = 1e-12)
      .def("solve", &PySolver::solve, py::arg("H"), py::arg("g"), py::arg("A_eq") = py::none(),
           py::arg("b_eq") = py::none(), py::arg("C") = py::none(), py::arg("d") = py::none(),
           py::arg("lb") = py::none(), py::arg("ub") = py::none())
      .def("reset_warm_start", [](PySolver& s) { s.core().reset_warm_start(); })
      .def_property_readonly("n", [](PySolver& s) { return s.core().max_variables(); })
      .def_property_readonly("max_eq", [](PySolver& s) { return s.core().max_equalities(); })
      .def_property_readonly("max_ineq", [](PySolver& s) { return s.core().max_inequalities(); });

  m.def(
      "solve",
      [](const py::object& H, const py::object& g, const py::object& A_eq, const py::object& b_eq,
         const py::object& C, const py::object& d, const py::object& lb, const py::object& ub,
         int max_iterations) {
        const Problem p = parse_any(H, g, A_eq, b_eq, C, d, lb, ub);
        PySolver s(p.n, p.me, p.mi, max_iterations, false, 1e-12);
        return s.solve_parsed(p);
      },
      py::arg("H"), py::arg("g"), py::arg("A_eq") = py::none(), py::arg("b_eq") = py::none(),
      py::arg("C") = py::none(), py::arg("d") = py::none(), py::arg("lb") = py::none(),
      py::arg("ub") = py::none(), py::arg("max_iterations") = 200,
      "min 1/2 x'Hx + g'x  s.t. A_eq x = b_eq, C x <= d, lb <= x <= ub (one row per constraint)");

  // Bench glue: wall time [ns] of each of `repeats` solves of one problem, timed in C++ around
  // DenseQpSolver::solve (no Python in the timed region); the first one runs with cold caches.
  m.def(
      "_time_solves",
      [](const py::object& H, const py::object& g, const py::object& A_eq, const py::object& b_eq,
         const py::object& C, const py::object& d, const py::object& lb, const py::object& ub,
         int repeats, bool warm_start) {
        const Problem p = parse_any(H, g, A_eq, b_eq, C, d, lb, ub);
        PySolver s(p.n, p.me, p.mi, 200, warm_start, 1e-12);
        s.load(p);
        py::array_t<std::int64_t> ns(std::max(repeats, 0));
        auto out = ns.mutable_unchecked<1>();
        for (int k = 0; k < repeats; ++k) {
          const auto t0 = std::chrono::steady_clock::now();
          s.run(p);
          const auto t1 = std::chrono::steady_clock::now();
          out(k) = std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count();
        }
        return ns;
      },
      py::arg("H"), py::arg("g"), py::arg("A_eq") = py::none(), py::arg("b_eq") = py::none(),
      py::arg("C") = py::none(), py::arg("d") = py::none(), py::arg("lb") = py::none(),
      py::arg("ub") = py::none(), py::arg("repeats") = 1000, py::arg("warm_start") = false);
}

}  // namespace kiloloop::py_glue
