#pragma once
// The loop's I/O: read() fills the controller input, write() takes its output. This one replays
// a back-to-back log (firmware/record.hpp) and compares every output with the logged one, bit
// for bit; a CAN or EtherCAT driver offers the same two calls (read the bus into the input, write
// the output to the bus). read()/write() allocate nothing and never throw.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "kiloloop/firmware/record.hpp"

namespace firmware {

struct Mismatch {
  long tick = -1;            // -1: none
  const char* field = "";    // the output field that differs
  int element = 0;           // index inside it
  std::int64_t firmware_bits = 0, log_bits = 0;
};

// The log's header against the exported robot (init time): the magic, the family, the record
// sizes. false with the reason in *why.
inline bool check_log_header(const kiloloop::LogHeader& h, bool header_read,
                             kiloloop::Family family, std::size_t in_bytes,
                             std::size_t out_bytes, std::string* why) {
  auto fail = [why](const std::string& msg) {
    *why = msg;
    return false;
  };
  if (!header_read || std::memcmp(h.magic, kiloloop::kLogMagic, sizeof h.magic) != 0)
    return fail("not a kiloloop b2b log");
  if (h.family != static_cast<std::int64_t>(family))
    return fail("the log is of another robot family than the exported robot");
  if (static_cast<std::size_t>(h.input_bytes) != in_bytes ||
      static_cast<std::size_t>(h.output_bytes) != out_bytes)
    return fail("record sizes differ from the exported robot's (" +
                std::to_string(h.input_bytes) + "/" + std::to_string(h.output_bytes) +
                " bytes in the log, " + std::to_string(in_bytes) + "/" +
                std::to_string(out_bytes) + " here): another robot's log?");
  return true;
}

// One tick's output against the logged one, bit for bit: true if equal; else *m holds the tick,
// the first differing field and element and both 8-byte words. scratch: out_bytes of room.
template <class Output>
bool compare_output(const Output& out, const unsigned char* expected, std::size_t out_bytes,
                    long tick, unsigned char* scratch, Mismatch* m) noexcept {
  kiloloop::write_record(out, scratch);
  if (std::memcmp(scratch, expected, out_bytes) == 0) return true;
  std::size_t k = 0;
  while (scratch[k] == expected[k]) ++k;
  kiloloop::FieldAt at(k);
  kiloloop::visit_fields(const_cast<Output&>(out), at);
  const std::size_t word = k / 8 * 8;
  m->tick = tick;
  m->field = at.name();
  m->element = at.element();
  std::memcpy(&m->firmware_bits, scratch + word, 8);
  std::memcpy(&m->log_bits, expected + word, 8);
  return false;
}

template <class Input, class Output>
class ReplayIo {
 public:
  // Reads the whole log (init time). Input/output give the sizes the records must have.
  bool open(const char* path, kiloloop::Family family, const Input& in, const Output& out,
            std::string* why) {
    std::FILE* f = std::fopen(path, "rb");
    if (!f) return fail(why, std::string("cannot open log '") + path + "'");
    kiloloop::LogHeader h{};
    const bool header_ok = std::fread(&h, sizeof h, 1, f) == 1;
    std::vector<unsigned char> body;
    unsigned char chunk[65536];
    for (std::size_t n; (n = std::fread(chunk, 1, sizeof chunk, f)) > 0;) body.insert(body.end(), chunk, chunk + n);
    std::fclose(f);
    in_bytes_ = kiloloop::record_bytes(in);
    out_bytes_ = kiloloop::record_bytes(out);
    if (!check_log_header(h, header_ok, family, in_bytes_, out_bytes_, why)) return false;
    const std::size_t tick_bytes = in_bytes_ + out_bytes_;
    if (body.empty() || body.size() % tick_bytes != 0) return fail(why, "truncated log");
    log_ = std::move(body);
    ticks_ = static_cast<long>(log_.size() / tick_bytes);
    scratch_.assign(out_bytes_, 0);
    return true;
  }

  long ticks() const { return ticks_; }

  // The next tick's input; past the end it starts over with t and stamp shifted by the log's
  // length (the timed run loops the log). Outputs are compared on the first pass only.
  void read(Input& in) noexcept {
    if (next_ == ticks_) {
      next_ = 0;
      ++pass_;
    }
    kiloloop::read_record(record(next_), in);
    if (pass_ == 0) return;  // the logged input exactly
    const double shift = static_cast<double>(pass_) * ticks_ * 0.001;  // [s] 1 kHz ticks
    in.t += shift;
    in.stamp += shift;
  }

  void write(const Output& out) noexcept {
    const long tick = next_++;
    if (pass_ > 0 || mismatch_.tick >= 0) return;
    if (compare_output(out, record(tick) + in_bytes_, out_bytes_, tick, scratch_.data(),
                       &mismatch_))
      ++identical_;
  }

  long identical_ticks() const { return identical_; }
  const Mismatch& mismatch() const { return mismatch_; }

 private:
  const unsigned char* record(long tick) const {
    return log_.data() + static_cast<std::size_t>(tick) * (in_bytes_ + out_bytes_);
  }
  static bool fail(std::string* why, const std::string& msg) {
    *why = msg;
    return false;
  }

  std::vector<unsigned char> log_, scratch_;
  std::size_t in_bytes_ = 0, out_bytes_ = 0;
  long ticks_ = 0, next_ = 0, pass_ = 0, identical_ = 0;
  Mismatch mismatch_;
};

}  // namespace firmware
