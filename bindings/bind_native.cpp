// kiloloop._core.native: the native SIL loop (cpp/sil/) over the mjModel/mjData of Python
// `mujoco.MjModel`/`MjData` objects (their `_address`). Thin: argument checks, keeping the Python
// objects alive while C++ borrows them, releasing the GIL around the loop.
#include "common.hpp"

#ifdef KILOLOOP_NATIVE_SIL
#include <dlfcn.h>

#include <cmath>

#include <cstdint>
#include <memory>
#include <optional>
#include <type_traits>
#include <vector>

#include "kiloloop/control/cartesian_impedance.hpp"
#include "kiloloop/control/computed_torque.hpp"
#include "kiloloop/control/hybrid_force_position.hpp"
#include "kiloloop/control/joint_pd_gravity.hpp"
#include "sil/aerial_adapter.hpp"
#include "sil/arm_adapters.hpp"
#include "sil/attitude_noise.hpp"
#include "sil/dropout_stage.hpp"
#include "sil/batch.hpp"
#include "sil/imu_model.hpp"
#include "sil/legged_sensor_stages.hpp"
#include "sil/mujoco_api.hpp"
#include "sil/native_loop.hpp"
#include "sil/press_adapter.hpp"
#include "sil/quadruped_adapter.hpp"
#include "sil/smooth_heightfield.hpp"
#include "sil/wind_drag.hpp"
#endif

namespace kiloloop::py_glue {

#ifdef KILOLOOP_NATIVE_SIL
namespace {

using namespace kiloloop::sil;

// An adapter plus the Python objects (controllers, trajectories) it borrows.
struct PyAdapter {
  std::shared_ptr<Adapter> adapter;
  std::vector<py::object> keep;
};

// A rollout plus the Python objects (MjModel, MjData, adapter) it borrows.
struct PyRollout {
  Rollout rollout;
  py::object model, data, adapter;
};

template <class T>
T* address_of(const py::object& obj, const char* name) {
  if (!py::hasattr(obj, "_address"))
    throw py::value_error(std::string(name) + ": expected a mujoco." +
                          (std::is_same_v<T, mjModel> ? "MjModel" : "MjData"));
  return reinterpret_cast<T*>(obj.attr("_address").cast<std::uintptr_t>());
}

JointTorqueController* joint_controller(const py::object& c) {
  if (py::isinstance<ComputedTorqueController>(c)) return &c.cast<ComputedTorqueController&>();
  if (py::isinstance<JointPdGravityController>(c)) return &c.cast<JointPdGravityController&>();
  throw py::value_error("controller: expected a ComputedTorqueController or JointPdGravityController");
}

CartesianTorqueController* cartesian_torque_controller(const py::object& c) {
  if (py::isinstance<HybridForcePositionController>(c)) return &c.cast<HybridForcePositionController&>();
  if (py::isinstance<CartesianImpedanceController>(c)) return &c.cast<CartesianImpedanceController&>();
  throw py::value_error("controller: expected a HybridForcePositionController or CartesianImpedanceController");
}

JointReference joint_reference(const py::object& r, int nq) {
  JointReference ref;
  if (py::isinstance<QuinticTrajectory>(r)) {
    ref = &r.cast<const QuinticTrajectory&>();
  } else if (py::isinstance<TrapezoidTrajectory>(r)) {
    ref = &r.cast<const TrapezoidTrajectory&>();
  } else {
    throw py::value_error("trajectory: expected a QuinticTrajectory or TrapezoidTrajectory");
  }
  const int n = std::visit([](auto* t) { return t->nq(); }, ref);
  if (n != nq) throw py::value_error("trajectory: has " + std::to_string(n) + " joints, the controller " + std::to_string(nq));
  return ref;
}

// Path of the shared object that defines the resolved mj_step (empty before load_mujoco).
std::string library_path() {
  Dl_info info{};
  const auto step = mujoco_api().step;
  if (step && dladdr(reinterpret_cast<void*>(step), &info) && info.dli_fname) return info.dli_fname;
  return "";
}

}  // namespace
#endif

void bind_native(py::module_& parent) {
  py::module_ m = parent.def_submodule("native", "native SIL loop (C++ closed loop on a MuJoCo plant)");
#ifndef KILOLOOP_NATIVE_SIL
  m.attr("available") = false;
#else
  m.attr("available") = true;
  m.attr("header_version") = mjVERSION_HEADER;
  m.def("load_mujoco",
        [](const std::string& path) {
          std::string why;
          if (!load_mujoco_api(path, &why)) throw py::value_error(why);
          return std::string(mujoco_api().version_string());
        },
        py::arg("path"), "resolves MuJoCo's functions from the already-loaded libmujoco at path");
  m.attr("smooth_heightfield_prefix") = kSmoothHeightfieldPrefix;
  m.def("install_smooth_heightfield",
        [] {
          std::string why;
          if (!install_smooth_heightfield(&why)) throw py::value_error(why);
        },
        "one contact per sphere on heightfields named kiloloop_smooth* (sil/smooth_heightfield.hpp)");
  m.def("sphere_on_bilinear",
        [](const Array& heights, double rx, double ry, double elevation, const Array& centre, double radius,
           double margin) -> py::object {
          if (heights.ndim() != 2 || centre.size() != 3) throw py::value_error("heights (nrow, ncol), centre (3)");
          std::vector<float> data(heights.data(), heights.data() + heights.size());
          double dist, pos[3], n[3];
          if (!sphere_on_bilinear(data.data(), static_cast<int>(heights.shape(0)), static_cast<int>(heights.shape(1)),
                                  rx, ry, elevation, centre.data(), radius, margin, &dist, pos, n))
            return py::none();
          return py::make_tuple(dist, Array(3, pos), Array(3, n));
        },
        py::arg("heights"), py::arg("rx"), py::arg("ry"), py::arg("elevation"), py::arg("centre"),
        py::arg("radius"), py::arg("margin") = 0.0,
        "the contact smooth_heightfield_sphere makes: (dist, pos, normal) or None (tests)");
  m.def("mujoco_loaded", &mujoco_api_loaded);
  m.def("mujoco_library", &library_path, "path of the libmujoco the native loop calls");

  py::class_<PyAdapter>(m, "Adapter", "a native adapter: measurement -> compiled controller -> command")
      .def_property_readonly("measurement_size", [](const PyAdapter& a) { return a.adapter->measurement_size(); })
      .def_property_readonly("command_size", [](const PyAdapter& a) { return a.adapter->command_size(); });

  m.def("joint_tracking_adapter",
        [](py::object controller, py::object trajectory) {
          JointTorqueController* c = joint_controller(controller);
          return PyAdapter{std::make_shared<JointTrackingAdapter>(c, joint_reference(trajectory, c->nq())),
                           {controller, trajectory}};
        },
        py::arg("controller"), py::arg("trajectory"),
        "y = [q; qd] -> computed torque / PD + gravity on a joint trajectory (JointTrackingTick)");
  m.def("cartesian_adapter",
        [](py::object controller, py::object line) {
          auto* c = &controller.cast<CartesianTrackingController&>();
          auto* l = &line.cast<const CartesianLine&>();
          return PyAdapter{std::make_shared<CartesianTrackingAdapter>(c, l), {controller, line}};
        },
        py::arg("controller"), py::arg("line"), "y = [q; qd] -> CartesianTrackingController on a CartesianLine");
  m.def("supervised_adapter",
        [](py::object controller, py::object supervisor, py::object trajectory) {
          JointTorqueController* c = joint_controller(controller);
          auto* s = &supervisor.cast<ArmSupervisor&>();
          if (s->nq() != c->nq()) throw py::value_error("supervisor: joint count differs from the controller's");
          return PyAdapter{std::make_shared<SupervisedAdapter>(c, s, joint_reference(trajectory, c->nq())),
                           {controller, supervisor, trajectory}};
        },
        py::arg("controller"), py::arg("supervisor"), py::arg("trajectory"),
        "y = [q; qd] -> joint controller -> ArmSupervisor (e-stop events) (SupervisedTick)");

  m.def("press_adapter",
        [](py::object controller, const Eigen::Vector3d& p0, const Eigen::Matrix3d& R0, double force,
           double settle, double slide, double slide_time) {
          CartesianTorqueController* c = cartesian_torque_controller(controller);
          if (!(slide_time > 0.0) || !std::isfinite(settle) || !std::isfinite(slide) || !std::isfinite(force) ||
              !p0.allFinite() || !R0.allFinite())
            throw py::value_error("press_adapter: expected finite p0, R0, force, settle, slide and slide_time > 0");
          PressSlide s;
          s.p0 = p0;
          s.settle = settle;
          s.slide = slide;
          s.slide_time = slide_time;
          return PyAdapter{std::make_shared<PressAdapter>(c, s, R0, force), {controller}};
        },
        py::arg("controller"), py::arg("p0"), py::arg("R0"), py::arg("force"), py::arg("settle"),
        py::arg("slide"), py::arg("slide_time"),
        "y = [q; qd; f_site (3); site quat (4)] -> hybrid force/position or impedance pressing `force` [N] "
        "down while p_ref slides `slide` [m] along x on a quintic from `settle` [s] (arm-press)");
  m.def("quadruped_adapter",
        [](py::object controller, std::array<int, 12> to_ctrl, int gait, const Eigen::Vector3d& velocity,
           bool ground_truth) {
          auto* c = &controller.cast<QuadrupedController&>();
          for (int j : to_ctrl)
            if (j < 0 || j >= 12) throw py::value_error("to_ctrl: expected plant joint indices 0..11");
          if (gait != 0 && gait != 1) throw py::value_error("gait: expected 0 (stand) or 1 (trot)");
          return PyAdapter{std::make_shared<QuadrupedAdapter>(c, to_ctrl, static_cast<Gait>(gait), velocity,
                                                              ground_truth),
                           {controller}};
        },
        py::arg("controller"), py::arg("to_ctrl"), py::arg("gait") = 0,
        py::arg("velocity") = Eigen::Vector3d::Zero().eval(), py::arg("ground_truth") = false,
        "y = [q; qd; gyro; accel; quat] (plant order) -> QuadrupedController -> tau (plant order); "
        "to_ctrl[j]: plant index of controller joint j; commands as reference events {gait, vx, vy, wz}; "
        "ground_truth: y += [base pos (3); base quat (4); base lin vel (3)] (qpos / qvel) fed to the controller");
  m.def("set_foothold_offset",
        [](PyAdapter& a, const Vector12d& offset) {
          auto* q = dynamic_cast<QuadrupedAdapter*>(a.adapter.get());
          if (!q) throw py::value_error("set_foothold_offset: not a quadruped adapter");
          q->set_foothold_offset(offset);
        },
        py::arg("adapter"), py::arg("offset"),
        "(12) [m] per foot, trunk frame, added to the swing footholds from the next tick on");

  m.def("aerial_adapter",
        [](py::object controller, std::vector<int> to_ctrl, const Array& references) {
          auto* c = &controller.cast<AerialController&>();
          if (static_cast<int>(to_ctrl.size()) != c->nq()) throw py::value_error("to_ctrl: expected one plant index per arm joint");
          for (int j : to_ctrl)
            if (j < 0 || j >= c->nq()) throw py::value_error("to_ctrl: expected plant joint indices 0..nq-1");
          if (references.ndim() != 2 || references.shape(0) < 1 || references.shape(1) != AerialAdapter::width(c->nq()))
            throw py::value_error("references: expected (rows >= 1, " + std::to_string(AerialAdapter::width(c->nq())) + ")");
          std::vector<double> table(references.data(), references.data() + references.size());
          for (double x : table)
            if (!std::isfinite(x)) throw py::value_error("references: non-finite value");
          return PyAdapter{std::make_shared<AerialAdapter>(c, std::move(to_ctrl), std::move(table)), {controller}};
        },
        py::arg("controller"), py::arg("to_ctrl"), py::arg("references"),
        "y = [position; velocity; gyro; accel; quat; q; qd] -> AerialController -> [thrust; tau] (plant order); "
        "references: one row per tick (AerialAdapter::Ref layout)");
  m.attr("AERIAL_REFERENCE_WIDTH") = static_cast<int>(AerialAdapter::kReferenceWidth);

  py::class_<SensorStage, std::shared_ptr<SensorStage>>(m, "SensorStage",
                                                        "a measurement stage after the sensor model (sensor_stage.hpp)")
      .def("configure", [](SensorStage& s, int n) {
        std::string why;
        if (!s.configure(n, &why)) throw py::value_error(why);
      }, py::arg("n"), "checks the stage fits a y of n entries (the per-tick loop calls it once)")
      .def("apply", [](SensorStage& s, double t, const Array& y) {
        Eigen::VectorXd out = Eigen::Map<const Eigen::VectorXd>(y.data(), y.size());
        s.apply(t, out.data());
        return out;
      }, py::arg("t"), py::arg("y"), "y after this stage at tick time t [s] (a copy)");
  py::class_<AttitudeNoise, SensorStage, std::shared_ptr<AttitudeNoise>>(
      m, "AttitudeNoise", "small random body-frame rotation of the quaternion y[offset..offset+3] (seeded)")
      .def(py::init([](int offset, double sigma, unsigned long long seed, int n) {
             auto s = std::make_shared<AttitudeNoise>(offset, sigma, seed);
             std::string why;
             if (!s->configure(n, &why)) throw py::value_error(why);
             return s;
           }),
           py::arg("offset"), py::arg("sigma"), py::arg("seed"), py::arg("n"));
  py::class_<DropoutStage, SensorStage, std::shared_ptr<DropoutStage>>(
      m, "DropoutStage", "y[offset..offset+count) frozen at its last value during [start, start + duration) [s]")
      .def(py::init([](int offset, int count, double start, double duration) {
             return std::make_shared<DropoutStage>(offset, count, start, duration);
           }),
           py::arg("offset"), py::arg("count"), py::arg("start"), py::arg("duration"));
  py::class_<Disturbance, std::shared_ptr<Disturbance>>(m, "Disturbance", "a per-tick wrench on a body (disturbance.hpp)");
  py::class_<WindDrag, Disturbance, std::shared_ptr<WindDrag>>(m, "WindDrag", "wind drag at a body's subtree CoM (wind_drag.hpp)")
      .def(py::init([](int body, int velocity_adr, const Eigen::Vector3d& steady, double ramp, double gust_sigma,
                       double gust_tau, double vertical_scale, double drag_area, double air_density, double dt,
                       unsigned long long seed) {
             WindDragConfig c;
             c.body = body;
             c.velocity_adr = velocity_adr;
             for (int i = 0; i < 3; ++i) c.steady[i] = steady[i];
             c.ramp = ramp;
             c.gust_sigma = gust_sigma;
             c.gust_tau = gust_tau;
             c.vertical_scale = vertical_scale;
             c.drag_area = drag_area;
             c.air_density = air_density;
             c.dt = dt;
             c.seed = seed;
             return std::make_shared<WindDrag>(c);
           }),
           py::arg("body"), py::arg("velocity_adr"), py::arg("steady"), py::arg("ramp"), py::arg("gust_sigma"),
           py::arg("gust_tau"), py::arg("vertical_scale"), py::arg("drag_area"), py::arg("air_density"),
           py::arg("dt"), py::arg("seed"))
      .def("check",
           [](WindDrag& w, py::object model) {
             LogBuffer scratch;
             std::string why;
             if (!w.configure(address_of<mjModel>(model, "model"), scratch, &why)) throw py::value_error(why);
           },
           py::arg("model"), "checks the settings against the model (the per-tick Python loop; a Rollout does it itself)")
      .def("apply",
           [](WindDrag& w, double t, py::object model, py::object data) {
             w.apply(t, address_of<mjModel>(model, "model"), address_of<mjData>(data, "data"));
           },
           py::arg("t"), py::arg("model"), py::arg("data"),
           "this tick's wind and drag, written into data.xfrc_applied of the body (the per-tick Python loop)")
      .def_property_readonly("wind", [](const WindDrag& w) { return Eigen::Vector3d(w.wind()); })
      .def_property_readonly("force", [](const WindDrag& w) { return Eigen::Vector3d(w.force()); });

  py::class_<PyRollout>(m, "Rollout", "one native closed-loop run on a MuJoCo model/data")
      .def(py::init([](py::object model, py::object data, py::object adapter, int ticks, double control_dt,
                       std::vector<int> measurement, std::vector<int> actuators, int delay_ticks,
                       std::vector<double> sigma, std::vector<double> quantum, unsigned long long seed,
                       int motor_delay_ticks, double motor_time_constant, std::vector<double> motor_limit,
                       py::list events, py::list probes, std::optional<py::tuple> stop,
                       std::vector<int> measurement_source, bool motor_hold_first,
                       std::vector<std::shared_ptr<SensorStage>> stages,
                       std::vector<std::shared_ptr<Disturbance>> disturbances, bool stop_nonfinite) {
             auto* pa = &adapter.cast<PyAdapter&>();
             RolloutConfig config;
             config.ticks = ticks;
             config.control_dt = control_dt;
             config.measurement = std::move(measurement);
             config.actuators = std::move(actuators);
             config.delay_ticks = delay_ticks;
             config.sensor.sigma = std::move(sigma);
             config.sensor.quantum = std::move(quantum);
             config.sensor.seed = seed;
             config.motor.delay_ticks = motor_delay_ticks;
             config.motor.time_constant = motor_time_constant;
             config.motor.limit = std::move(motor_limit);
             config.motor.hold_first = motor_hold_first;
             config.measurement_source = std::move(measurement_source);
             config.sensor_stages = std::move(stages);
             config.disturbances = std::move(disturbances);
             config.stop_nonfinite = stop_nonfinite;
             for (auto item : events) {
               auto e = item.cast<py::tuple>();
               if (e.size() != 3) throw py::value_error("events: expected (time, kind, payload) tuples");
               const int kind = e[1].cast<int>();
               if (kind < 0 || kind > 3)
                 throw py::value_error("events: kind must be 0 (estop), 1 (reference), 2 (force) or 3 (gain)");
               config.events.push_back(Event{e[0].cast<double>(), static_cast<EventKind>(kind),
                                             e[2].cast<std::vector<double>>()});
             }
             for (auto item : probes) {
               auto p = item.cast<py::tuple>();
               if (p.size() != 3) throw py::value_error("probes: expected (name, source, index) tuples");
               const int source = p[1].cast<int>();
               if (source < 0 || source > Probe::kLastSource)
                 throw py::value_error("probes: source must be 0.." + std::to_string(Probe::kLastSource));
               config.probes.push_back(Probe{p[0].cast<std::string>(), static_cast<Probe::Source>(source),
                                             p[2].cast<std::vector<int>>()});
             }
             if (stop) {
               if (stop->size() != 3) throw py::value_error("stop: expected (probe index, element, below)");
               config.stop_probe = (*stop)[0].cast<int>();
               config.stop_element = (*stop)[1].cast<int>();
               config.stop_below = (*stop)[2].cast<double>();
             }
             auto r = std::make_unique<PyRollout>();
             std::string why;
             if (!r->rollout.configure(address_of<mjModel>(model, "model"), address_of<mjData>(data, "data"),
                                       pa->adapter, std::move(config), &why))
               throw py::value_error(why);
             r->model = model;
             r->data = data;
             r->adapter = adapter;
             return r;
           }),
           py::arg("model"), py::arg("data"), py::arg("adapter"), py::kw_only(), py::arg("ticks"),
           py::arg("control_dt") = 0.001, py::arg("measurement"), py::arg("actuators"),
           py::arg("delay_ticks") = 0, py::arg("sigma") = std::vector<double>{},
           py::arg("quantum") = std::vector<double>{}, py::arg("seed") = 0ULL,
           py::arg("motor_delay_ticks") = 0, py::arg("motor_time_constant") = 0.0,
           py::arg("motor_limit") = std::vector<double>{}, py::arg("events") = py::list(),
           py::arg("probes") = py::list(), py::arg("stop") = py::none(),
           py::arg("measurement_source") = std::vector<int>{}, py::arg("motor_hold_first") = false,
           py::arg("stages") = std::vector<std::shared_ptr<SensorStage>>{},
           py::arg("disturbances") = std::vector<std::shared_ptr<Disturbance>>{},
           py::arg("stop_nonfinite") = false)
      .def("record_io",
           [](PyRollout& r) {
             std::string why;
             if (!r.rollout.record_io(&why)) throw py::value_error(why);
           },
           "from the first tick on, keep every controller input and output record (the b2b log's)")
      .def("io_records",
           [](const PyRollout& r) {
             const auto sizes = r.rollout.io_sizes();
             const size_t n = static_cast<size_t>(r.rollout.result().ticks) * sizes.total();
             return py::make_tuple(
                 py::bytes(reinterpret_cast<const char*>(r.rollout.io_records().data()), n),
                 sizes.input, sizes.output);
           },
           "(records of the ticks run, input bytes, output bytes) per tick, after record_io")
      .def("run",
           [](PyRollout& r) {
             py::gil_scoped_release no_gil;
             r.rollout.run();
           },
           "runs the remaining ticks from the data's current state (GIL released)")
      .def("advance",
           [](PyRollout& r, int n) {
             py::gil_scoped_release no_gil;
             r.rollout.advance(n);
           },
           py::arg("n"), "runs up to n more ticks (GIL released)")
      .def_property_readonly("stopped", [](const PyRollout& r) { return r.rollout.result().stopped; })
      .def_property_readonly("diverged", [](const PyRollout& r) { return r.rollout.result().diverged; })
      .def_property_readonly("finished", [](const PyRollout& r) { return r.rollout.finished(); })
      .def("last",
           [](const PyRollout& r, const std::string& name) {
             const int k = r.rollout.result().ticks - 1;
             const auto& channels = r.rollout.log().channels();
             for (size_t id = 0; id < channels.size(); ++id)
               if (channels[id].name == name) {
                 if (k < 0) throw py::value_error("last: no tick run yet");
                 Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(
                     r.rollout.log().row(static_cast<int>(id), k), channels[id].width);
                 return v;
               }
             throw py::value_error("last: no channel " + name);
           },
           py::arg("name"), "the channel's row at the last tick run (flat copy)")
      .def_property_readonly("ok", [](const PyRollout& r) { return r.rollout.result().ok; })
      .def_property_readonly("error", [](const PyRollout& r) { return r.rollout.result().error; })
      .def_property_readonly("ticks_run", [](const PyRollout& r) { return r.rollout.result().ticks; })
      .def_property_readonly("warnings", [](const PyRollout& r) { return r.rollout.result().warnings; })
      .def("log",
           [](const PyRollout& r) {
             py::dict out;
             const int ticks = r.rollout.result().ticks;  // rows actually written
             const auto& channels = r.rollout.log().channels();
             for (size_t id = 0; id < channels.size(); ++id) {
               std::vector<py::ssize_t> shape{ticks};
               for (int s : channels[id].shape) shape.push_back(s);
               py::array_t<double> a(shape);
               r.rollout.log().copy_channel(static_cast<int>(id), ticks, a.mutable_data());
               out[py::str(channels[id].name)] = a;
             }
             return out;
           },
           "{channel: (ticks_run, *shape) array}, copies");

  m.def("run_batch",
        [](py::list rollouts, int threads) {
          std::vector<Rollout*> rs;
          for (auto item : rollouts) rs.push_back(&item.cast<PyRollout&>().rollout);
          py::gil_scoped_release no_gil;
          run_batch(rs, threads);
        },
        py::arg("rollouts"), py::arg("threads"),
        "runs every Rollout once on a pool of C++ threads (GIL released); each must own its data");
  m.def("advance_batch",
        [](py::list rollouts, int ticks, int threads) {
          std::vector<Rollout*> rs;
          for (auto item : rollouts) rs.push_back(&item.cast<PyRollout&>().rollout);
          py::gil_scoped_release no_gil;
          advance_batch(rs, ticks, threads);
        },
        py::arg("rollouts"), py::arg("ticks"), py::arg("threads"),
        "advances every Rollout by up to `ticks` on a pool of C++ threads (GIL released)");
  m.def("step_adapter",
        [](PyAdapter& a, const Array& y, int n, double dt) {
          vector_arg(y, a.adapter->measurement_size(), "y");
          py::gil_scoped_release no_gil;
          step_adapter(*a.adapter, y.data(), n, dt);
        },
        py::arg("adapter"), py::arg("y"), py::arg("n"), py::arg("dt") = 0.001,
        "n adapter (controller) steps on a fixed measurement, no physics (bench reference)");
  m.def("step_raw",
        [](py::object model, py::object data, int n, std::optional<Array> ctrl, std::vector<int> actuators) {
          auto* mm = address_of<mjModel>(model, "model");
          auto* dd = address_of<mjData>(data, "data");
          const int k = static_cast<int>(actuators.size());
          if (ctrl) {
            if (ctrl->ndim() != 2 || ctrl->shape(0) < n || ctrl->shape(1) != k)
              throw py::value_error("ctrl: expected shape (>= n, len(actuators))");
            for (int a : actuators)
              if (a < 0 || a >= mm->nu) throw py::value_error("actuators: index out of range");
          }
          const double* c = ctrl ? ctrl->data() : nullptr;
          py::gil_scoped_release no_gil;
          step_raw(mm, dd, n, c, actuators.data(), k);
        },
        py::arg("model"), py::arg("data"), py::arg("n"), py::arg("ctrl") = py::none(),
        py::arg("actuators") = std::vector<int>{},
        "n x mj_step from C++ (bench reference); ctrl rows replayed onto ctrl[actuators]");

  // The sensor and motor models alone, for the per-tick Python loop (same code, same stream).
  py::class_<SensorModel>(m, "SensorModel", "noise + quantization over a flat signal vector")
      .def(py::init([](std::vector<double> sigma, std::vector<double> quantum, unsigned long long seed, int n) {
             SensorModel s;
             std::string why;
             if (!s.configure(SensorModelConfig{std::move(sigma), std::move(quantum), seed}, n, &why))
               throw py::value_error(why);
             return s;
           }),
           py::arg("sigma"), py::arg("quantum"), py::arg("seed"), py::arg("n"))
      .def("apply", [](SensorModel& s, const Array& x) {
        vector_arg(x, s.size(), "x");
        Eigen::VectorXd y(x.size());
        s.apply(x.data(), y.data());
        return y;
      });
  py::class_<MotorModel>(m, "MotorModel", "command transport delay [ticks] + first-order lag")
      .def(py::init([](int delay_ticks, double time_constant, double dt, int n, std::vector<double> limit,
                       bool hold_first) {
             MotorModel s;
             std::string why;
             if (!s.configure(MotorModelConfig{delay_ticks, time_constant, dt, std::move(limit), hold_first}, n, &why))
               throw py::value_error(why);
             return s;
           }),
           py::arg("delay_ticks"), py::arg("time_constant"), py::arg("dt"), py::arg("n"),
           py::arg("limit") = std::vector<double>{}, py::arg("hold_first") = false)
      .def("push", [](MotorModel& s, const Array& u) {
        vector_arg(u, s.size(), "u");
        Eigen::VectorXd y(u.size());
        s.push(u.data(), y.data());
        return y;
      });

  // Measurement stages after the sensor model (sil/legged_sensor_stages.hpp): the native loop
  // runs them from Rollout(stages=[...]), the per-tick Python loop through apply(t, y); each
  // run must have its own (they carry state and random streams).
  {
    const ImuModelConfig d;  // BMI088 defaults: one place for both loops' settings
    py::dict defaults;
    defaults["gyro"] = py::make_tuple(d.gyro.noise_density, d.gyro.bias_random_walk, d.gyro.turn_on_bias);
    defaults["accel"] = py::make_tuple(d.accel.noise_density, d.accel.bias_random_walk, d.accel.turn_on_bias);
    m.attr("imu_defaults") = defaults;
  }
  py::class_<ImuStage, SensorStage, std::shared_ptr<ImuStage>>(
      m, "ImuStage", "MEMS IMU errors on y[offset:offset+6] = [gyro; accel] (cpp/sil/imu_model.hpp)")
      .def(py::init([](int offset, std::array<double, 3> gyro, std::array<double, 3> accel, double dt,
                       unsigned long long seed) {
             auto s = std::make_shared<ImuStage>();
             std::string why;
             const ImuModelConfig c{InertialNoise{gyro[0], gyro[1], gyro[2]},
                                    InertialNoise{accel[0], accel[1], accel[2]}, dt, seed};
             if (!s->setup(c, offset, &why)) throw py::value_error(why);
             return s;
           }),
           py::arg("offset"), py::arg("gyro"), py::arg("accel"), py::arg("dt"), py::arg("seed"),
           "gyro, accel: (noise density, bias random walk, turn-on bias sigma) each")
      .def_property_readonly("bias", [](const ImuStage& s) {
        return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(s.model().bias(), ImuModel::kSize));
      });
  py::class_<JointEncoderStage, SensorStage, std::shared_ptr<JointEncoderStage>>(
      m, "JointEncoderStage", "encoder-difference joint velocity, then q quantized")
      .def(py::init([](int n, int q_offset, int qd_offset, double q_resolution, double velocity_resolution,
                       double dt) {
             auto s = std::make_shared<JointEncoderStage>();
             std::string why;
             if (!s->setup(n, q_offset, qd_offset, q_resolution, velocity_resolution, dt, &why))
               throw py::value_error(why);
             return s;
           }),
           py::arg("n"), py::arg("q_offset"), py::arg("qd_offset"), py::arg("q_resolution"),
           py::arg("velocity_resolution"), py::arg("dt"));
#endif
}

}  // namespace kiloloop::py_glue
