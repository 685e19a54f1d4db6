#pragma once
// Glue shared by the bind_*.cpp files: shape checks that raise ValueError naming the argument,
// and conversion of a failed configure() Status into a Python exception.
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "kiloloop/status.hpp"

namespace kiloloop::py_glue {

namespace py = pybind11;
using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A read-only Eigen view of a 1-D array of length n; ValueError "name: expected shape (n,)".
inline Eigen::Map<const Eigen::VectorXd> vector_arg(const Array& a, Eigen::Index n, const char* name) {
  if (a.ndim() != 1 || a.shape(0) != n)
    throw py::value_error(std::string(name) + ": expected shape (" + std::to_string(n) + ",)");
  return Eigen::Map<const Eigen::VectorXd>(a.data(), n);
}

// A configure()/create() failure becomes ValueError with the reason.
inline void raise_if_failed(Status s, const std::string& why) {
  if (failed(s)) throw py::value_error(why.empty() ? std::string(to_string(s)) : why);
}

// Vector members appear in Python as numpy views into the C++ struct (writes go straight in, no
// copy per tick); assigning a new array replaces the vector (dynamic sizes: any size, so that
// step() can report BAD_SIZE; fixed sizes: must match, ValueError otherwise).
template <class Class, class Vector>
void vector_field(py::class_<Class>& cls, const char* name, Vector Class::*member, const char* doc) {
  cls.def_property(
      name,
      py::cpp_function([member](Class& self) -> Eigen::Ref<Vector> { return self.*member; },
                       py::return_value_policy::reference_internal),
      [member](Class& self, const Vector& v) { self.*member = v; }, doc);
}

void bind_status(py::module_& m);
void bind_model(py::module_& m);
void bind_dynamics(py::module_& m);
void bind_trajectory(py::module_& m);
void bind_control(py::module_& m);
void bind_quadruped(py::module_& m);
void bind_qp(py::module_& m);
void bind_kinematics(py::module_& m);
void bind_arm(py::module_& m);
void bind_calibration(py::module_& m);
void bind_planning(py::module_& m);
void bind_force(py::module_& m);
void bind_safety(py::module_& m);
void bind_aerial(py::module_& m);
void bind_native(py::module_& m);

}  // namespace kiloloop::py_glue
