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

// Input record, then output record (sized like io_record_bytes at configure).
template <class In, class Out>
void write_io_record(const In& in, const Out& out, unsigned char* p) noexcept {
  write_record(in, p);
  write_record(out, p + record_bytes(in));
}

}  // namespace kiloloop::sil
