// kl.detmath: the deterministic math (docs/firmware.md) for Python code that must compute what
// the compiled core computes, bit for bit (a twin of a C++ program, examples/embed/embed_twin.py).
// Each is the C library's function as this module binds it: musl's (cpp/detmath/libm_names.c),
// not the interpreter's math.sin (the system's libm, whose results depend on the CPU).
#include <cmath>

#include "common.hpp"

namespace kiloloop::py_glue {

void bind_detmath(py::module_& m) {
  auto d = m.def_submodule("detmath", "musl's C math, as the compiled core calls it");
  d.def("sin", [](double x) { return std::sin(x); }, py::arg("x"));
  d.def("cos", [](double x) { return std::cos(x); }, py::arg("x"));
  d.def("tan", [](double x) { return std::tan(x); }, py::arg("x"));
  d.def("asin", [](double x) { return std::asin(x); }, py::arg("x"));
  d.def("acos", [](double x) { return std::acos(x); }, py::arg("x"));
  d.def("atan", [](double x) { return std::atan(x); }, py::arg("x"));
  d.def("atan2", [](double y, double x) { return std::atan2(y, x); }, py::arg("y"), py::arg("x"));
  d.def("sinh", [](double x) { return std::sinh(x); }, py::arg("x"));
  d.def("cosh", [](double x) { return std::cosh(x); }, py::arg("x"));
  d.def("tanh", [](double x) { return std::tanh(x); }, py::arg("x"));
  d.def("exp", [](double x) { return std::exp(x); }, py::arg("x"));
  d.def("expm1", [](double x) { return std::expm1(x); }, py::arg("x"));
  d.def("log", [](double x) { return std::log(x); }, py::arg("x"));
  d.def("log1p", [](double x) { return std::log1p(x); }, py::arg("x"));
  d.def("pow", [](double x, double y) { return std::pow(x, y); }, py::arg("x"), py::arg("y"));
  d.def("cbrt", [](double x) { return std::cbrt(x); }, py::arg("x"));
  d.def("hypot", [](double x, double y) { return std::hypot(x, y); }, py::arg("x"), py::arg("y"));
}

}  // namespace kiloloop::py_glue
