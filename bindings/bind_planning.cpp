// Trapezoid trajectory, capsule-box collision model, RRT-Connect planning (glue only).
#include "common.hpp"
#include "kiloloop/planning/rrt_connect.hpp"
#include "kiloloop/urdf/collision_capsules.hpp"

namespace kiloloop::py_glue {
namespace {

struct PlanResult {
  Status status = Status::kOk;
  std::string message;
  std::optional<TrapezoidTrajectory> trajectory;
  Eigen::MatrixXd path;  // (m, nq) one waypoint per row
  PlanStats stats;
};

TrapezoidTrajectory make_trapezoid(const Eigen::MatrixXd& waypoints, const Eigen::VectorXd& v_max,
                                   const Eigen::VectorXd& a_max, double t0) {
  TrapezoidTrajectory traj;
  std::string why;
  // Python passes one waypoint per row (m, nq); the core stores columns.
  raise_if_failed(TrapezoidTrajectory::configure(waypoints.transpose(), v_max, a_max, t0, &traj, &why), why);
  return traj;
}

}  // namespace

void bind_planning(py::module_& m) {
  py::class_<TrapezoidTrajectory>(m, "TrapezoidTrajectory",
                                  "Synchronized trapezoidal-velocity joint trajectory through waypoints "
                                  "(rest at each, straight joint-space segments, per-joint v/a limits)")
      .def(py::init(&make_trapezoid), py::arg("waypoints"), py::arg("v_max"), py::arg("a_max"),
           py::arg("t0") = 0.0)
      .def_property_readonly("nq", &TrapezoidTrajectory::nq)
      .def_property_readonly("start_time", &TrapezoidTrajectory::start_time)
      .def_property_readonly("end_time", &TrapezoidTrajectory::end_time)
      .def_property_readonly("times", &TrapezoidTrajectory::times)
      .def("sample",
           [](const TrapezoidTrajectory& traj, double t) {
             Eigen::VectorXd q(traj.nq()), qd(traj.nq()), qdd(traj.nq());
             traj.sample(t, q, qd, qdd);
             return py::make_tuple(q, qd, qdd);
           },
           py::arg("t"), "(q, qd, qdd) at time t [s]")
      .def("sample_into",
           [](const TrapezoidTrajectory& traj, double t, Eigen::Ref<Eigen::VectorXd> q,
              Eigen::Ref<Eigen::VectorXd> qd, Eigen::Ref<Eigen::VectorXd> qdd) {
             return traj.sample(t, q, qd, qdd);
           },
           py::arg("t"), py::arg("q"), py::arg("qd"), py::arg("qdd"),
           "Writes into preallocated float64 arrays; returns Status");

  py::class_<LinkCapsule>(m, "LinkCapsule", "Capsule (segment a-b, radius) fixed in a link frame [m]")
      .def(py::init<>())
      .def_readwrite("link", &LinkCapsule::link)
      .def_readwrite("a", &LinkCapsule::a)
      .def_readwrite("b", &LinkCapsule::b)
      .def_readwrite("radius", &LinkCapsule::radius)
      .def("__repr__", [](const LinkCapsule& c) {
        return "LinkCapsule(" + c.link + ", r=" + std::to_string(c.radius) + ")";
      });
  py::class_<OrientedBox>(m, "OrientedBox", "Box obstacle: center [m], rotation (3,3), half_extents [m]")
      .def(py::init([](const Eigen::Vector3d& center, const Eigen::Vector3d& half_extents,
                       const std::optional<Eigen::Matrix3d>& rotation) {
             OrientedBox b;
             b.center = center;
             b.half_extents = half_extents;
             if (rotation) b.rotation = *rotation;
             return b;
           }),
           py::arg("center"), py::arg("half_extents"), py::arg("rotation") = py::none())
      .def_readwrite("center", &OrientedBox::center)
      .def_readwrite("half_extents", &OrientedBox::half_extents)
      .def_readwrite("rotation", &OrientedBox::rotation);
  m.def("segment_box_distance", &segment_box_distance, py::arg("a"), py::arg("b"), py::arg("box"),
        "Exact distance [m] from segment [a, b] to the box (0 when they intersect)");
  m.def("capsules_from_urdf",
        [](const std::string& path_or_xml, const RobotModel& model, const std::optional<py::dict>& mesh_capsules) {
          // {link: [LinkCapsule or (a, b, radius)]} in the link frame, for mesh collisions.
          MeshCapsules given;
          if (mesh_capsules) {
            for (const auto& [key, value] : *mesh_capsules) {
              const std::string link = py::cast<std::string>(key);
              auto& list = given[link];
              for (const py::handle& item : value) {
                if (py::isinstance<LinkCapsule>(item)) {
                  list.push_back(py::cast<LinkCapsule>(item));
                  continue;
                }
                const py::sequence t = py::reinterpret_borrow<py::sequence>(item);
                if (t.size() != 3)
                  throw py::value_error("mesh_capsules['" + link + "']: expected LinkCapsule or (a, b, radius)");
                LinkCapsule c;
                c.link = link;
                c.a = py::cast<Eigen::Vector3d>(t[0]);
                c.b = py::cast<Eigen::Vector3d>(t[1]);
                c.radius = py::cast<double>(t[2]);
                list.push_back(c);
              }
            }
          }
          std::vector<LinkCapsule> caps;
          std::string why;
          const bool is_xml = path_or_xml.find('<') != std::string::npos;
          raise_if_failed(is_xml ? capsules_from_urdf_string(path_or_xml, model, given, &caps, &why)
                                 : capsules_from_urdf_file(path_or_xml, model, given, &caps, &why),
                          why);
          return caps;
        },
        py::arg("path_or_xml"), py::arg("model"), py::arg("mesh_capsules") = py::none(),
        "Capsules bounding the URDF <collision> geometry of the model's chain links (and of the\n"
        "links folded onto them), in chain order. Mesh collisions need mesh_capsules: {link:\n"
        "[LinkCapsule or (a, b, radius)]} in that link's frame (kiloloop.meshes.capsules_for_urdf).");

  py::class_<ArmCollisionChecker>(m, "ArmCollisionChecker", "Link capsules vs box obstacles (exact)")
      .def(py::init([](std::shared_ptr<RobotModel> model, const std::vector<LinkCapsule>& capsules,
                       const std::vector<OrientedBox>& boxes, double margin) {
             ArmCollisionConfig cfg;
             cfg.capsules = capsules;
             cfg.boxes = boxes;
             cfg.margin = margin;
             ArmCollisionChecker c;
             std::string why;
             raise_if_failed(ArmCollisionChecker::configure(cfg, model, &c, &why), why);
             return c;
           }),
           py::arg("model"), py::arg("capsules"), py::arg("boxes"), py::arg("margin") = 0.01)
      .def("clearance",
           [](ArmCollisionChecker& c, const Array& q) { return c.clearance(vector_arg(q, c.nq(), "q")); },
           py::arg("q"), "smallest capsule-box distance minus the margin [m]")
      .def("is_free", [](ArmCollisionChecker& c, const Array& q) { return c.is_free(vector_arg(q, c.nq(), "q")); },
           py::arg("q"))
      .def("segment_free",
           [](ArmCollisionChecker& c, const Array& q0, const Array& q1, double max_step) {
             return c.segment_free(vector_arg(q0, c.nq(), "q0"), vector_arg(q1, c.nq(), "q1"), max_step);
           },
           py::arg("q0"), py::arg("q1"), py::arg("max_step") = 0.02)
      .def_property_readonly("checks", &ArmCollisionChecker::checks);

  py::class_<RrtConfig>(m, "RrtConfig")
      .def(py::init<>())
      .def_readwrite("max_iterations", &RrtConfig::max_iterations)
      .def_readwrite("extend_step", &RrtConfig::extend_step)
      .def_readwrite("collision_step", &RrtConfig::collision_step)
      .def_readwrite("shortcut_iterations", &RrtConfig::shortcut_iterations)
      .def_readwrite("seed", &RrtConfig::seed)
      .def_readwrite("lower", &RrtConfig::lower)
      .def_readwrite("upper", &RrtConfig::upper);
  py::class_<PlanStats>(m, "PlanStats")
      .def_readonly("iterations", &PlanStats::iterations)
      .def_readonly("tree_nodes", &PlanStats::tree_nodes)
      .def_readonly("raw_waypoints", &PlanStats::raw_waypoints)
      .def_readonly("waypoints", &PlanStats::waypoints)
      .def_readonly("raw_length", &PlanStats::raw_length)
      .def_readonly("length", &PlanStats::length)
      .def_readonly("collision_checks", &PlanStats::collision_checks);
  py::class_<PlanResult>(m, "PlanResult")
      .def_readonly("status", &PlanResult::status)
      .def_readonly("message", &PlanResult::message)
      .def_readonly("trajectory", &PlanResult::trajectory)
      .def_readonly("path", &PlanResult::path)
      .def_readonly("stats", &PlanResult::stats);
  m.def("plan_trajectory",
        [](ArmCollisionChecker& checker, const RrtConfig& config, const Array& q_start, const Array& q_goal,
           const Array& v_max, const Array& a_max, double t0) {
          const int n = checker.nq();
          PlanResult r;
          TrapezoidTrajectory traj;
          Eigen::MatrixXd path;
          r.status = plan_trajectory(checker, config, vector_arg(q_start, n, "q_start"),
                                     vector_arg(q_goal, n, "q_goal"), vector_arg(v_max, n, "v_max"),
                                     vector_arg(a_max, n, "a_max"), t0, &traj, &path, &r.stats, &r.message);
          if (r.status == Status::kInvalidConfig) throw py::value_error(r.message);
          if (r.status == Status::kOk) r.trajectory = std::move(traj);
          r.path = path.transpose();
          return r;
        },
        py::arg("checker"), py::arg("config"), py::arg("q_start"), py::arg("q_goal"), py::arg("v_max"),
        py::arg("a_max"), py::arg("t0") = 0.0,
        "RRT-Connect + shortcutting + trapezoid time-parameterization; PlanResult.status says if it worked");
}

}  // namespace kiloloop::py_glue
