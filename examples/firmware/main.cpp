// kiloloop_firmware: one exported robot (robot_export.hpp, written by `kiloloop export`) in the
// shape firmware has: init (may allocate, may fail with a reason), then a loop of
// read inputs -> controller step -> write outputs that allocates nothing.
//
//   kiloloop_firmware replay LOG          every logged input, as fast as possible; every output
//                                         compared with the logged one bit for bit; prints
//                                         "bit-identical: N ticks" (exit 0) or the first differing
//                                         tick and field (exit 1)
//   kiloloop_firmware run LOG SECONDS     the same inputs (the log looped) at 1 kHz on absolute
//                                         deadlines; prints the wake-up latency histogram, the
//                                         step time and the deadline overruns
//   kiloloop_firmware pil LOG             replay, with the step between the PIL markers, then the
//                                         footprint: heap held by init, the steps' stack
//                                         high-water mark (footprint.hpp; `kiloloop pil` runs it
//                                         on the target under QEMU)
//   kiloloop_firmware model-check ROOT TIP STATES OUT
//                                         the exported description's chain ROOT -> TIP: mass
//                                         matrix, gravity and Coriolis at the states in STATES
//                                         (binary doubles q, qd per state) into OUT (binary)
//
// Built with -fno-exceptions -fno-rtti (CMakeLists.txt).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "family.hpp"
#include "footprint.hpp"
#include "kiloloop/dynamics/dynamics.hpp"
#include "replay_io.hpp"
#include "robot_export.hpp"
#if KILOLOOP_FIRMWARE_BARE_METAL
// A microcontroller (cortex_m7/): the log streamed from the host's file, no POSIX clock (no
// `run`); newlib's printf has no C99 formats (%a, %zu): doubles printed in 17 digits.
#include "replay_stream_io.hpp"
#define KILOLOOP_FMT_DOUBLE "%.17g"
#else
#include "fixed_rate.hpp"
#define KILOLOOP_FMT_DOUBLE "%a"
#endif

namespace {

int fail(const char* what, const std::string& why) {
  std::fprintf(stderr, "kiloloop_firmware: %s: %s\n", what, why.c_str());
  return 2;
}

struct Firmware {
  kiloloop::RobotModelPtr model;
  exported::Controller controller;
  exported::Input in;
  exported::Output out;
#if KILOLOOP_FIRMWARE_BARE_METAL
  firmware::StreamReplayIo<exported::Input, exported::Output> io;
#else
  firmware::ReplayIo<exported::Input, exported::Output> io;
#endif
};

// Init: the model from the exported description, the controller from the exported settings.
int init_controller(Firmware* fw) {
  std::string why;
  if (kiloloop::failed(exported::make_model(&fw->model, &why)))
    return fail("cannot build the exported model", why);
  if (kiloloop::failed(exported::Controller::configure(exported::make_config(), fw->model,
                                                       &fw->controller, &why)))
    return fail("cannot configure the controller", why);
  firmware::make_io(fw->controller, &fw->in, &fw->out);
  return 0;
}

// Init, then the replayed log.
int init(Firmware* fw, const char* log) {
  if (int rc = init_controller(fw)) return rc;
  std::string why;
  if (!fw->io.open(log, exported::kFamily, fw->in, fw->out, &why)) return fail("log", why);
  return 0;
}

// One tick: read the inputs, step, write the outputs.
void tick(Firmware& fw) noexcept {
  fw.io.read(fw.in);
  fw.controller.step(fw.in, fw.out);
  fw.io.write(fw.out);
}

// The same tick with the step alone between the PIL markers (footprint.hpp).
void tick_marked(Firmware& fw) noexcept {
  fw.io.read(fw.in);
  kiloloop_pil_step_begin();
  fw.controller.step(fw.in, fw.out);
  kiloloop_pil_step_end();
  fw.io.write(fw.out);
}

int report_identity(const Firmware& fw, long ticks) {
  const firmware::Mismatch& m = fw.io.mismatch();
  if (m.tick < 0) {
    std::printf("bit-identical: %ld ticks\n", ticks);
    return 0;
  }
  double a, b;
  std::memcpy(&a, &m.firmware_bits, 8);
  std::memcpy(&b, &m.log_bits, 8);
  std::printf("differs at tick %ld: output field %s[%d]: firmware " KILOLOOP_FMT_DOUBLE
              " (0x%016llx), SIL log " KILOLOOP_FMT_DOUBLE " (0x%016llx) (%ld ticks identical "
              "before)\n",
              m.tick, m.field, m.element, a, (unsigned long long)m.firmware_bits, b,
              (unsigned long long)m.log_bits, fw.io.identical_ticks());
  return 1;
}

int replay(const char* log) {
  auto fw = std::make_unique<Firmware>();
  if (int rc = init(fw.get(), log)) return rc;
  for (long k = 0; k < fw->io.ticks(); ++k) tick(*fw);
  return report_identity(*fw, fw->io.ticks());
}

// The replay as the processor-in-the-loop run does it: the heap init holds (the log's buffer
// not counted), the steps' stack high-water mark, then the identity line.
int pil(const char* log) {
  auto fw = std::make_unique<Firmware>();
  const std::size_t heap_before = firmware::heap_in_use();
  if (int rc = init_controller(fw.get())) return rc;
  const std::size_t heap_init = firmware::heap_in_use() - heap_before;
  std::string why;
  if (!fw->io.open(log, exported::kFamily, fw->in, fw->out, &why)) return fail("log", why);
  const firmware::StackPaint paint = firmware::paint_stack();
  for (long k = 0; k < fw->io.ticks(); ++k) tick_marked(*fw);
  const std::size_t stack = firmware::stack_reached(paint);
  // %lu, not %zu: newlib's printf (the bare-metal build) has no C99 size modifier.
  std::printf("heap held by init: %lu bytes\n", static_cast<unsigned long>(heap_init));
  std::printf("stack high-water of the steps: %s%lu bytes\n",
              stack >= firmware::kStackPaintBytes ? "at least " : "",
              static_cast<unsigned long>(stack));
  return report_identity(*fw, fw->io.ticks());
}

#if !KILOLOOP_FIRMWARE_BARE_METAL
int run(const char* log, double seconds) {
  auto fw = std::make_unique<Firmware>();
  if (int rc = init(fw.get(), log)) return rc;
  const firmware::RealtimeSetup rt = firmware::enter_realtime();
  std::printf("%s (%s): %.1f s at 1 kHz; SCHED_FIFO %s, mlockall %s\n", exported::kRobotName,
              exported::kFamilyName, seconds, rt.fifo ? "on" : "not permitted (ordinary scheduling)",
              rt.locked ? "on" : "not permitted");
  const long ticks = static_cast<long>(seconds * 1000.0 + 0.5);
  const firmware::LoopReport r = firmware::run_fixed_rate(ticks, [&fw]() noexcept { tick(*fw); });
  r.histogram.print("wake-up latency (deadline -> awake):");
  std::printf("wake-up latency: median %.1f us, p99 %.1f us, max %.1f us\n", r.wake.median_ns / 1e3,
              r.wake.p99_ns / 1e3, r.wake.max_ns / 1e3);
  std::printf("step (read + controller + write): median %.1f us, p99 %.1f us, max %.1f us\n",
              r.step.median_ns / 1e3, r.step.p99_ns / 1e3, r.step.max_ns / 1e3);
  std::printf("ticks %ld, deadline overruns %ld\n", r.ticks, r.overruns);
  std::printf("first pass through the log (%ld ticks): ", fw->io.ticks());
  return report_identity(*fw, std::min(ticks, fw->io.ticks()));
}
#endif

int model_check(const char* root, const char* tip, const char* states_path, const char* out_path) {
  std::string why;
  auto model = std::make_shared<kiloloop::RobotModel>();
  if (kiloloop::failed(kiloloop::model_from_description(exported::kDescription, root, tip, {},
                                                        model.get(), &why)))
    return fail("model", why);
  kiloloop::Dynamics dyn;
  if (kiloloop::failed(kiloloop::Dynamics::configure(model, Eigen::Vector3d(0.0, 0.0, -9.81), &dyn, &why)))
    return fail("dynamics", why);
  const int nq = dyn.nq();
  std::FILE* in = std::fopen(states_path, "rb");
  std::FILE* out = std::fopen(out_path, "wb");
  if (!in || !out) return fail("model-check", "cannot open the state or output file");
  Eigen::VectorXd q(nq), qd(nq), g(nq), c(nq);
  Eigen::MatrixXd M(nq, nq);
  while (std::fread(q.data(), 8, nq, in) == static_cast<std::size_t>(nq) &&
         std::fread(qd.data(), 8, nq, in) == static_cast<std::size_t>(nq)) {
    dyn.mass_matrix(q, M);
    dyn.gravity(q, g);
    dyn.coriolis(q, qd, c);
    std::fwrite(M.data(), 8, nq * nq, out);  // column-major
    std::fwrite(g.data(), 8, nq, out);
    std::fwrite(c.data(), 8, nq, out);
  }
  std::fclose(in);
  std::fclose(out);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3 && std::strcmp(argv[1], "replay") == 0) return replay(argv[2]);
  if (argc == 3 && std::strcmp(argv[1], "pil") == 0) return pil(argv[2]);
#if !KILOLOOP_FIRMWARE_BARE_METAL
  if (argc == 4 && std::strcmp(argv[1], "run") == 0) return run(argv[2], std::atof(argv[3]));
#endif
  if (argc == 6 && std::strcmp(argv[1], "model-check") == 0)
    return model_check(argv[2], argv[3], argv[4], argv[5]);
  std::fprintf(stderr,
               "usage: %s replay LOG | pil LOG | run LOG SECONDS | model-check ROOT TIP STATES "
               "OUT\n", argv[0]);
  return 2;
}
