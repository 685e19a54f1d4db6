// kiloloop._core: the compiled core, re-exported by the `kiloloop` package.
#include "common.hpp"

namespace kiloloop::py_glue {
void bind_firmware(py::module_& m);  // bind_firmware.cpp
void bind_detmath(py::module_& m);   // bind_detmath.cpp
void bind_field_docs(py::module_& m);  // field_docs.cpp: after every class is bound
}  // namespace kiloloop::py_glue

PYBIND11_MODULE(_core, m) {
  using namespace kiloloop::py_glue;
  m.doc() = "kiloloop compiled core (C++): models, dynamics, trajectories, controllers";
  m.attr("__version__") = KILOLOOP_VERSION;
  bind_status(m);
  bind_model(m);
  bind_dynamics(m);
  bind_trajectory(m);
  bind_control(m);
  bind_quadruped(m);
  bind_qp(m);
  bind_kinematics(m);
  bind_arm(m);
  bind_calibration(m);
  bind_planning(m);
  bind_force(m);
  bind_safety(m);
  bind_aerial(m);
  bind_native(m);
  bind_firmware(m);
  bind_detmath(m);
  bind_field_docs(m);
}
