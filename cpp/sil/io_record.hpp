#pragma once
// A controller's input and output as back-to-back log records (kiloloop/firmware/record.hpp),
// for the native loop's adapters: the same bytes the firmware replay reads, written in C++ at
// each tick, so a recorded SIL run needs no per-tick Python.
#include <cstddef>

#include "kiloloop/firmware/record.hpp"

namespace kiloloop::sil {

struct IoRecordBytes {
  std::size_t input = 0;   // per tick
  std::size_t output = 0;
  std::size_t total() const { return input + output; }
};

template <class In, class Out>
IoRecordBytes io_record_bytes(const In& in, const Out& out) {
  return {record_bytes(in), record_bytes(out)};
}

// Input record, then output record, at p; sizes: io_record_bytes(in, out) from configure (the
// rollout keeps it), so a recorded tick does not walk the input's fields twice to size it.
template <class In, class Out>
void write_io_record(const In& in, const Out& out, const IoRecordBytes& sizes, unsigned char* p) noexcept {
  write_record(in, p);
  write_record(out, p + sizes.input);
}

}  // namespace kiloloop::sil
