/* Bare-metal start of the firmware on a Cortex-M7 (QEMU's mps2-an500; an STM32H7 starts the
 * same way): the vector table, the reset handler (FPU on before any floating-point instruction,
 * .data copied from flash, .bss zeroed), then newlib's semihosting C library (librdimon: stdio
 * and the host's files through the debugger, here QEMU), argv from the semihosting command line
 * (QEMU's -semihosting-config arg=...), main, and exit with main's code (QEMU exits with it).
 * Linked with -nostartfiles (mps2_an500.ld): this file replaces rdimon-crt0, which takes the
 * stack and heap from the debugger (SYS_HEAPINFO) and copies no .data. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Linker script symbols (mps2_an500.ld). */
extern uint32_t __stack_top, __stack_limit;
extern uint32_t __data_start__, __data_end__, __data_load__, __bss_start__, __bss_end__;

/* newlib and librdimon. */
extern void initialise_monitor_handles(void);
extern void __libc_init_array(void);
extern unsigned int __heap_limit;  /* rdimon's _sbrk never grows the heap past it: set at reset */
int main(int argc, char** argv);

/* What crti.o and crtbegin.o would define (not linked with -nostartfiles): __libc_init_array
 * calls _init (nothing to do: constructors are in .init_array), libstdc++ registers its
 * destructors with __cxa_atexit against __dso_handle (one executable, no shared objects). */
void _init(void) {}
void _fini(void) {}
__attribute__((visibility("hidden"))) void* __dso_handle = &__dso_handle;

/* One semihosting call (Arm's semihosting v2; on M-profile the trap is BKPT 0xAB). */
enum {
  kSysWrite0 = 0x04,       /* write a NUL-terminated string to the host's console */
  kSysGetCmdline = 0x15,   /* the command line QEMU was given (arg=...) */
  kSysExitExtended = 0x20  /* exit with a status code */
};
static int semihost(int op, void* arg) {
  register int r0 __asm__("r0") = op;
  register void* r1 __asm__("r1") = arg;
  __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

static void die(const char* what, int code) {
  uint32_t block[2] = {0x20026u /* ADP_Stopped_ApplicationExit */, (uint32_t)code};
  semihost(kSysWrite0, (void*)what);
  semihost(kSysExitExtended, block);
  for (;;) {
  }
}

/* Faults end the run with a message and exit code 3 (no debugger to stop in). */
static void fault_handler(void) { die("kiloloop_firmware: fault (hard/memory/bus/usage)\n", 3); }

/* argv from the semihosting command line, split at spaces (paths with spaces are not
 * supported). */
enum { kMaxArgs = 8, kCmdlineBytes = 512 };
static char cmdline[kCmdlineBytes];
static char* argv_[kMaxArgs + 1];

static int read_argv(void) {
  struct {
    char* buf;
    int len;
  } block = {cmdline, kCmdlineBytes - 1};
  if (semihost(kSysGetCmdline, &block) != 0) return 0;
  cmdline[block.len < kCmdlineBytes ? block.len : kCmdlineBytes - 1] = '\0';
  int argc = 0;
  for (char* p = cmdline; *p && argc < kMaxArgs;) {
    while (*p == ' ') *p++ = '\0';
    if (!*p) break;
    argv_[argc++] = p;
    while (*p && *p != ' ') ++p;
  }
  argv_[argc] = 0;
  return argc;
}

/* After the FPU is on: C runtime, then main. */
__attribute__((noreturn, used)) void kiloloop_m7_start(void) {
  memcpy(&__data_start__, &__data_load__,
         (size_t)((char*)&__data_end__ - (char*)&__data_start__));
  memset(&__bss_start__, 0, (size_t)((char*)&__bss_end__ - (char*)&__bss_start__));
  __heap_limit = (unsigned int)(uintptr_t)&__stack_limit;
  initialise_monitor_handles();
  __libc_init_array();
  const int argc = read_argv();
  exit(main(argc, argv_));
}

/* Reset: the FPU (CP10, CP11) gets full access in CPACR before any floating-point instruction
 * (GCC may use the FPU's registers in any C function built with -mfloat-abi=hard), then the C
 * runtime. The core loaded SP from the vector table. */
__attribute__((naked, noreturn)) void Reset_Handler(void) {
  __asm__ volatile(
      "ldr r0, =0xE000ED88\n"  /* CPACR */
      "ldr r1, [r0]\n"
      "orr r1, r1, #(0xF << 20)\n"
      "str r1, [r0]\n"
      "dsb\n"
      "isb\n"
      "b kiloloop_m7_start\n");
}

/* The Cortex-M7's 16 system exception vectors (no device interrupts are used). */
typedef void (*Vector)(void);
__attribute__((section(".isr_vector"), used)) const Vector kVectors[16] = {
    (Vector)(uintptr_t)&__stack_top,  /* initial main stack pointer */
    Reset_Handler,
    fault_handler,  /* NMI */
    fault_handler,  /* HardFault */
    fault_handler,  /* MemManage */
    fault_handler,  /* BusFault */
    fault_handler,  /* UsageFault */
    0, 0, 0, 0,
    fault_handler,  /* SVCall */
    fault_handler,  /* DebugMonitor */
    0,
    fault_handler,  /* PendSV */
    fault_handler,  /* SysTick */
};
