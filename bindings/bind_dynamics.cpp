#include "common.hpp"
#include "kiloloop/dynamics/dynamics.hpp"

namespace kiloloop::py_glue {
namespace {

// Dynamics calls from Python check shapes up front (ValueError) and turn a failed Status
// (non-finite input) into ValueError too: this is the offline API, not the 1 kHz step.
void check(Status s) {
  if (failed(s)) throw py::value_error(std::string("dynamics call failed: ") + to_string(s));
}

}  // namespace

void bind_dynamics(py::module_& m) {
  py::class_<Dynamics>(m, "Dynamics", "Workspace for FK, Jacobian, RNE, M, C qd and g over a serial chain")
      .def(py::init([](std::shared_ptr<RobotModel> model, std::array<double, 3> g) {
             Dynamics d;
             std::string why;
             raise_if_failed(Dynamics::configure(model, Eigen::Vector3d(g[0], g[1], g[2]), &d, &why), why);
             return d;
           }),
           py::arg("model"), py::arg("gravity") = std::array<double, 3>{0.0, 0.0, -9.81})
      .def_property_readonly("nq", &Dynamics::nq)
      .def("inverse_dynamics",
           [](Dynamics& d, const Array& q, const Array& qd, const Array& qdd) {
             Eigen::VectorXd tau(d.nq());
             check(d.inverse_dynamics(vector_arg(q, d.nq(), "q"), vector_arg(qd, d.nq(), "qd"),
                                      vector_arg(qdd, d.nq(), "qdd"), tau));
             return tau;
           },
           py::arg("q"), py::arg("qd"), py::arg("qdd"), "M(q) qdd + C(q,qd) qd + g(q)  (nq,) [N m]")
      .def("mass_matrix",
           [](Dynamics& d, const Array& q) {
             Eigen::MatrixXd M(d.nq(), d.nq());
             check(d.mass_matrix(vector_arg(q, d.nq(), "q"), M));
             return M;
           },
           py::arg("q"))
      .def("coriolis",
           [](Dynamics& d, const Array& q, const Array& qd) {
             Eigen::VectorXd c(d.nq());
             check(d.coriolis(vector_arg(q, d.nq(), "q"), vector_arg(qd, d.nq(), "qd"), c));
             return c;
           },
           py::arg("q"), py::arg("qd"), "C(q, qd) qd  (nq,) [N m]")
      .def("gravity",
           [](Dynamics& d, const Array& q) {
             Eigen::VectorXd g(d.nq());
             check(d.gravity(vector_arg(q, d.nq(), "q"), g));
             return g;
           },
           py::arg("q"))
      .def("forward_kinematics",
           [](Dynamics& d, const Array& q) {
             Eigen::Matrix4d T;
             check(d.forward_kinematics(vector_arg(q, d.nq(), "q"), T));
             return T;
           },
           py::arg("q"), "(4, 4) tip pose in the root frame")
      .def("jacobian",
           [](Dynamics& d, const Array& q) {
             Eigen::MatrixXd J(6, d.nq());
             check(d.jacobian(vector_arg(q, d.nq(), "q"), J));
             return J;
           },
           py::arg("q"), "(6, nq) [linear; angular] in the root frame, at the tip");
}

}  // namespace kiloloop::py_glue
