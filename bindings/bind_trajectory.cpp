#include "common.hpp"
#include "kiloloop/trajectory/quintic.hpp"

namespace kiloloop::py_glue {

void bind_trajectory(py::module_& m) {
  py::class_<QuinticTrajectory>(m, "QuinticTrajectory",
                                "Quintic through waypoints (rest at the ends, Craig's via velocities)")
      .def(py::init([](const Eigen::MatrixXd& waypoints, const Eigen::VectorXd& times) {
             // Python passes one waypoint per row (m, nq); the core stores columns.
             if (waypoints.rows() != times.size())
               throw py::value_error("waypoints: expected shape (len(times), nq)");
             QuinticTrajectory traj;
             std::string why;
             raise_if_failed(QuinticTrajectory::configure(waypoints.transpose(), times, &traj, &why), why);
             return traj;
           }),
           py::arg("waypoints"), py::arg("times"))
      .def_property_readonly("nq", &QuinticTrajectory::nq)
      .def_property_readonly("start_time", &QuinticTrajectory::start_time)
      .def_property_readonly("end_time", &QuinticTrajectory::end_time)
      .def("sample",
           [](const QuinticTrajectory& traj, double t) {
             Eigen::VectorXd q(traj.nq()), qd(traj.nq()), qdd(traj.nq());
             traj.sample(t, q, qd, qdd);
             return py::make_tuple(q, qd, qdd);
           },
           py::arg("t"), "(q, qd, qdd) at time t [s]")
      .def("sample_into",
           [](const QuinticTrajectory& traj, double t, Eigen::Ref<Eigen::VectorXd> q,
              Eigen::Ref<Eigen::VectorXd> qd, Eigen::Ref<Eigen::VectorXd> qdd) {
             return traj.sample(t, q, qd, qdd);
           },
           py::arg("t"), py::arg("q"), py::arg("qd"), py::arg("qdd"),
           "Writes into preallocated float64 arrays (e.g. a JointControlInput's fields); returns Status");
}

}  // namespace kiloloop::py_glue
