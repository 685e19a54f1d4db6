#include "sil/arm_adapters.hpp"

#include <algorithm>

namespace kiloloop::sil {

namespace {
void store(const Eigen::VectorXd& v, double* row) noexcept { std::copy(v.data(), v.data() + v.size(), row); }
}  // namespace

void JointReferenceSampler::configure(JointReference reference, int nq) {
  reference_ = reference;
  offset_ = Eigen::VectorXd::Zero(nq);
  has_offset_ = false;
}

void JointReferenceSampler::sample(double t, JointControlInput& in) const noexcept {
  std::visit([&](auto* traj) { traj->sample(t, in.q_ref, in.qd_ref, in.qdd_ref); }, reference_);
  if (has_offset_) in.q_ref += offset_;
}

void JointReferenceSampler::set_offset(const Event& event) noexcept {
  if (event.kind != EventKind::kReference || static_cast<int>(event.payload.size()) != offset_.size()) return;
  for (int i = 0; i < offset_.size(); ++i) offset_[i] = event.payload[i];
  has_offset_ = true;
}

// --- joint tracking -------------------------------------------------------------------------
JointTrackingAdapter::JointTrackingAdapter(JointTorqueController* controller, JointReference reference)
    : c_(controller), nq_(controller->nq()) {
  ref_.configure(reference, nq_);
  in_ = controller->make_input();
  out_ = controller->make_output();
}

void JointTrackingAdapter::declare(LogBuffer& log) {
  ch_q_ = log.declare("q", {nq_});
  ch_qd_ = log.declare("qd", {nq_});
  ch_q_ref_ = log.declare("q_ref", {nq_});
  ch_tau_ = log.declare("tau", {nq_});
  ch_status_ = log.declare("status", {});
}

void JointTrackingAdapter::on_event(const Event& event) noexcept { ref_.set_offset(event); }

int JointTrackingAdapter::step(double t, double stamp, const double* y, double* u, LogBuffer& log,
                               int k) noexcept {
  in_.t = t;
  in_.stamp = stamp;
  in_.q = Eigen::Map<const Eigen::VectorXd>(y, nq_);
  in_.qd = Eigen::Map<const Eigen::VectorXd>(y + nq_, nq_);
  ref_.sample(t, in_);
  const int status = static_cast<int>(c_->step(in_, out_));
  store(in_.q, log.row(ch_q_, k));
  store(in_.qd, log.row(ch_qd_, k));
  store(in_.q_ref, log.row(ch_q_ref_, k));
  store(out_.tau, log.row(ch_tau_, k));
  *log.row(ch_status_, k) = status;
  std::copy(out_.tau.data(), out_.tau.data() + nq_, u);
  return status;
}

// --- Cartesian tracking ---------------------------------------------------------------------
CartesianTrackingAdapter::CartesianTrackingAdapter(CartesianTrackingController* controller,
                                                   const CartesianLine* line)
    : c_(controller), line_(line), nq_(controller->nq()) {
  in_ = controller->make_input();
  out_ = controller->make_output();
}

void CartesianTrackingAdapter::declare(LogBuffer& log) {
  ch_q_ = log.declare("q", {nq_});
  ch_q_ref_ = log.declare("q_ref", {nq_});
  ch_tau_ = log.declare("tau", {nq_});
  ch_pose_ref_ = log.declare("pose_ref", {4, 4});
  ch_ik_error_ = log.declare("ik_error", {6});
  ch_status_ = log.declare("status", {});
}

void CartesianTrackingAdapter::on_event(const Event& event) noexcept {
  if (event.kind == EventKind::kReference && event.payload.size() == 3) {
    offset_ = Eigen::Vector3d(event.payload[0], event.payload[1], event.payload[2]);
    has_offset_ = true;
  }
}

int CartesianTrackingAdapter::step(double t, double stamp, const double* y, double* u, LogBuffer& log,
                                   int k) noexcept {
  in_.t = t;
  in_.stamp = stamp;
  in_.q = Eigen::Map<const Eigen::VectorXd>(y, nq_);
  in_.qd = Eigen::Map<const Eigen::VectorXd>(y + nq_, nq_);
  // As CartesianLine.sample_into in the bindings: pose and twist only.
  Eigen::Isometry3d T;
  Vector6d accel;
  line_->sample(t, T, in_.twist_ref, accel);
  in_.pose_ref = T.matrix();
  if (has_offset_) in_.pose_ref.block<3, 1>(0, 3) += offset_;
  const int status = static_cast<int>(c_->step(in_, out_));
  store(in_.q, log.row(ch_q_, k));
  store(out_.q_ref, log.row(ch_q_ref_, k));
  store(out_.tau, log.row(ch_tau_, k));
  double* pose = log.row(ch_pose_ref_, k);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) pose[4 * r + c] = in_.pose_ref(r, c);  // row-major, as numpy
  std::copy(out_.task_error.data(), out_.task_error.data() + 6, log.row(ch_ik_error_, k));
  *log.row(ch_status_, k) = status;
  std::copy(out_.tau.data(), out_.tau.data() + nq_, u);
  return status;
}

// --- supervised joint tracking ----------------------------------------------------------------
SupervisedAdapter::SupervisedAdapter(JointTorqueController* controller, ArmSupervisor* supervisor,
                                     JointReference reference)
    : c_(controller), s_(supervisor), nq_(controller->nq()) {
  ref_.configure(reference, nq_);
  cin_ = controller->make_input();
  cout_ = controller->make_output();
  sin_ = supervisor->make_input();
  sout_ = supervisor->make_output();
}

void SupervisedAdapter::declare(LogBuffer& log) {
  ch_q_ = log.declare("q", {nq_});
  ch_qd_ = log.declare("qd", {nq_});
  ch_q_ref_ = log.declare("q_ref", {nq_});
  ch_tau_ = log.declare("tau", {nq_});
  ch_mode_ = log.declare("mode", {});
  ch_status_ = log.declare("status", {});
  ch_manip_ = log.declare("manipulability", {});
}

void SupervisedAdapter::on_event(const Event& event) noexcept {
  if (event.kind == EventKind::kEstop && !event.payload.empty()) estop_ = event.payload[0] != 0.0;
  ref_.set_offset(event);
}

int SupervisedAdapter::step(double t, double stamp, const double* y, double* u, LogBuffer& log,
                            int k) noexcept {
  cin_.t = t;
  cin_.stamp = stamp;
  cin_.q = Eigen::Map<const Eigen::VectorXd>(y, nq_);
  cin_.qd = Eigen::Map<const Eigen::VectorXd>(y + nq_, nq_);
  ref_.sample(t, cin_);
  c_->step(cin_, cout_);
  sin_.t = t;
  sin_.stamp = stamp;
  sin_.q = cin_.q;
  sin_.qd = cin_.qd;
  sin_.tau_command = cout_.tau;
  sin_.estop = estop_;
  const int status = static_cast<int>(s_->step(sin_, sout_));
  store(cin_.q, log.row(ch_q_, k));
  store(cin_.qd, log.row(ch_qd_, k));
  store(cin_.q_ref, log.row(ch_q_ref_, k));
  store(sout_.tau, log.row(ch_tau_, k));
  *log.row(ch_mode_, k) = static_cast<int>(sout_.mode);
  *log.row(ch_status_, k) = status;
  *log.row(ch_manip_, k) = sout_.singularity.manipulability;
  std::copy(sout_.tau.data(), sout_.tau.data() + nq_, u);
  return status;
}

}  // namespace kiloloop::sil
