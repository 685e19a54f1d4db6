/* kiloloop_insn_counter: a QEMU TCG plugin (user mode and system mode alike) that counts the
 * guest instructions executed between two marker functions of the firmware, once per controller
 * step: the PIL run's "instructions per step" (python/kiloloop/firmware/pil.py).
 *
 *   qemu-aarch64 -plugin libkiloloop_insn_counter.so,begin=0x4005d0,end=0x4005e0,out=FILE ...
 *
 * begin, end: the entry addresses of kiloloop_pil_step_begin and kiloloop_pil_step_end (the
 * firmware calls them just before and just after Controller::step; found with the target's nm).
 * Every executed instruction adds one to a counter (inline, no callback); entering `begin` takes
 * a snapshot, entering `end` records the difference. So a step's count includes the few
 * instructions of the two calls themselves (about 10 on either ISA).
 * At exit FILE gets one line: "steps N min A median B max C total T" (T: the whole run's count).
 * Built against qemu-plugin.h of the QEMU the machine has (Debian's source tarball, fetched and
 * hash-checked at build time: cmake/pil_plugin.cmake); API version 1 (QEMU 6.0 to 8.x). */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <qemu-plugin.h>

QEMU_PLUGIN_EXPORT int qemu_plugin_version = QEMU_PLUGIN_VERSION;

static uint64_t executed;         /* every guest instruction so far */
static uint64_t begin_addr, end_addr;
static uint64_t step_start;       /* `executed` when the current step began */
static uint64_t* steps;           /* instructions of each finished step */
static size_t n_steps, cap_steps;
static char out_path[4096];

static void on_begin(unsigned int vcpu, void* udata) {
  (void)vcpu, (void)udata;
  step_start = executed;
}

static void on_end(unsigned int vcpu, void* udata) {
  (void)vcpu, (void)udata;
  if (n_steps == cap_steps) {
    cap_steps = cap_steps ? 2 * cap_steps : 4096;
    steps = realloc(steps, cap_steps * sizeof *steps);
    if (!steps) abort();
  }
  steps[n_steps++] = executed - step_start;
}

static void on_translate(qemu_plugin_id_t id, struct qemu_plugin_tb* tb) {
  (void)id;
  const size_t n = qemu_plugin_tb_n_insns(tb);
  for (size_t i = 0; i < n; ++i) {
    struct qemu_plugin_insn* insn = qemu_plugin_tb_get_insn(tb, i);
    qemu_plugin_register_vcpu_insn_exec_inline(insn, QEMU_PLUGIN_INLINE_ADD_U64, &executed, 1);
    const uint64_t at = qemu_plugin_insn_vaddr(insn);
    if (at == begin_addr)
      qemu_plugin_register_vcpu_insn_exec_cb(insn, on_begin, QEMU_PLUGIN_CB_NO_REGS, NULL);
    else if (at == end_addr)
      qemu_plugin_register_vcpu_insn_exec_cb(insn, on_end, QEMU_PLUGIN_CB_NO_REGS, NULL);
  }
}

static int compare(const void* a, const void* b) {
  const uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
  return (x > y) - (x < y);
}

static void at_exit(qemu_plugin_id_t id, void* udata) {
  (void)id, (void)udata;
  FILE* f = fopen(out_path, "w");
  if (!f) return;
  if (n_steps == 0) {
    fprintf(f, "steps 0 min 0 median 0 max 0 total %" PRIu64 "\n", executed);
  } else {
    qsort(steps, n_steps, sizeof *steps, compare);
    fprintf(f, "steps %zu min %" PRIu64 " median %" PRIu64 " max %" PRIu64 " total %" PRIu64 "\n",
            n_steps, steps[0], steps[n_steps / 2], steps[n_steps - 1], executed);
  }
  fclose(f);
}

QEMU_PLUGIN_EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t* info, int argc,
                                           char** argv) {
  (void)info;
  for (int i = 0; i < argc; ++i) {
    if (strncmp(argv[i], "begin=", 6) == 0) begin_addr = strtoull(argv[i] + 6, NULL, 0);
    else if (strncmp(argv[i], "end=", 4) == 0) end_addr = strtoull(argv[i] + 4, NULL, 0);
    else if (strncmp(argv[i], "out=", 4) == 0) snprintf(out_path, sizeof out_path, "%s", argv[i] + 4);
    else {
      fprintf(stderr, "kiloloop_insn_counter: unknown argument '%s' (begin=, end=, out=)\n", argv[i]);
      return -1;
    }
  }
  if (!begin_addr || !end_addr || !out_path[0]) {
    fprintf(stderr, "kiloloop_insn_counter: begin=ADDR end=ADDR out=FILE are required\n");
    return -1;
  }
  qemu_plugin_register_vcpu_tb_trans_cb(id, on_translate);
  qemu_plugin_register_atexit_cb(id, at_exit, NULL);
  return 0;
}
