#pragma once
// What a processor-in-the-loop run measures on the target besides the bits (`kiloloop pil`):
//   step markers   two empty functions called just before and just after Controller::step; the
//                  QEMU instruction-counting plugin (cpp/pil/insn_counter.c) counts the guest
//                  instructions between their entries, one figure per step
//   stack          the step's stack high-water mark: the stack below the loop's frame is painted
//                  with a pattern before the loop; afterwards the deepest byte no longer holding
//                  the pattern tells how far the steps' frames reached
//   heap           bytes the C library's allocator holds, before and after init (model, controller)
// Static sizes (text, data, bss) come from the target's `size` on the executable.
#include <cstddef>
#include <cstdint>
#include <malloc.h>

extern "C" {
// noinline, with an empty asm statement: a call the optimizer cannot remove or merge.
__attribute__((noinline, used)) inline void kiloloop_pil_step_begin() { __asm__ volatile(""); }
__attribute__((noinline, used)) inline void kiloloop_pil_step_end() { __asm__ volatile(""); }
}

namespace firmware {

// Bytes of stack painted below the loop's frame [bytes]: more than any step of the three
// families uses (the PIL report says "at least" when every painted byte was reached).
constexpr std::size_t kStackPaintBytes = 48 * 1024;
constexpr unsigned char kStackPattern = 0xA5;

struct StackPaint {
  std::uintptr_t low = 0, high = 0;  // the painted addresses [low, high)
};

// Paints kStackPaintBytes just below the caller's frame. noinline: the painted array is this
// function's own frame, which lies where the caller's next calls (the steps) put theirs.
__attribute__((noinline)) inline StackPaint paint_stack() {
  volatile unsigned char area[kStackPaintBytes];
  for (std::size_t i = 0; i < kStackPaintBytes; ++i) area[i] = kStackPattern;
  StackPaint p;
  p.low = reinterpret_cast<std::uintptr_t>(&area[0]);
  p.high = p.low + kStackPaintBytes;
  return p;
}

// How many painted bytes, from the top of the painted area down, calls since paint_stack()
// reached [bytes] (the stack grows down on every target here).
__attribute__((noinline)) inline std::size_t stack_reached(const StackPaint& p) {
  const volatile unsigned char* byte = reinterpret_cast<const volatile unsigned char*>(p.low);
  std::size_t untouched = 0;
  while (untouched < kStackPaintBytes && byte[untouched] == kStackPattern) ++untouched;
  return kStackPaintBytes - untouched;
}

// Bytes the allocator holds for the program now (glibc: mallinfo2; newlib: mallinfo).
inline std::size_t heap_in_use() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  return mallinfo2().uordblks;
#else
  return static_cast<std::size_t>(mallinfo().uordblks);
#endif
}

}  // namespace firmware
