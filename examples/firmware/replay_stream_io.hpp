#pragma once
// ReplayIo's twin for a target whose RAM cannot hold the log (a Cortex-M7: 1 MB, where 2 s of
// the quadruped's log are 1.8 MB): the log stays in the file (on the bare-metal build, the host's
// file through semihosting) and each read() takes one tick's record from it, one C library read
// per tick (unbuffered: no stdio buffer in RAM, one semihosting call). The same calls and the
// same comparison as ReplayIo (replay_io.hpp); RAM held: one tick's record and the scratch
// output, a few hundred bytes to 3 KB. A failed read (the file shrank, a semihosting error) is
// reported as a mismatch at that tick, field "(log read failed)".
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "kiloloop/firmware/record.hpp"
#include "replay_io.hpp"  // Mismatch, check_log_header, compare_output

namespace firmware {

template <class Input, class Output>
class StreamReplayIo {
 public:
  StreamReplayIo() = default;
  StreamReplayIo(const StreamReplayIo&) = delete;
  StreamReplayIo& operator=(const StreamReplayIo&) = delete;
  ~StreamReplayIo() {
    if (file_) std::fclose(file_);
  }

  // Opens the log and checks its header (init time). Input/output give the record sizes.
  bool open(const char* path, kiloloop::Family family, const Input& in, const Output& out,
            std::string* why) {
    file_ = std::fopen(path, "rb");
    if (!file_) return fail(why, std::string("cannot open log '") + path + "'");
    std::setvbuf(file_, nullptr, _IONBF, 0);  // one read per record, no buffer held
    kiloloop::LogHeader h{};
    const bool header_ok = std::fread(&h, sizeof h, 1, file_) == 1;
    in_bytes_ = kiloloop::record_bytes(in);
    out_bytes_ = kiloloop::record_bytes(out);
    if (!check_log_header(h, header_ok, family, in_bytes_, out_bytes_, why)) return false;
    // The tick count from the file's length (semihosting: SYS_FLEN).
    if (std::fseek(file_, 0, SEEK_END) != 0) return fail(why, "cannot seek in the log");
    const long length = std::ftell(file_);
    const std::size_t tick_bytes = in_bytes_ + out_bytes_;
    const long body = length - static_cast<long>(sizeof h);
    if (body <= 0 || static_cast<std::size_t>(body) % tick_bytes != 0)
      return fail(why, "truncated log");
    ticks_ = static_cast<long>(static_cast<std::size_t>(body) / tick_bytes);
    if (std::fseek(file_, static_cast<long>(sizeof h), SEEK_SET) != 0)
      return fail(why, "cannot seek in the log");
    record_.assign(tick_bytes, 0);
    scratch_.assign(out_bytes_, 0);
    return true;
  }

  long ticks() const { return ticks_; }

  // The next tick's input, exactly as logged. One pass through the log: the bare-metal firmware
  // replays it once (`replay`, `pil`); looping it is the POSIX `run` command's, ReplayIo's.
  void read(Input& in) noexcept {
    read_ok_ = std::fread(record_.data(), 1, record_.size(), file_) == record_.size();
    kiloloop::read_record(record_.data(), in);
  }

  void write(const Output& out) noexcept {
    const long tick = next_++;
    if (mismatch_.tick >= 0) return;
    if (!read_ok_) {
      mismatch_.tick = tick;
      mismatch_.field = "(log read failed)";
      return;
    }
    if (compare_output(out, record_.data() + in_bytes_, out_bytes_, tick, scratch_.data(),
                       &mismatch_))
      ++identical_;
  }

  long identical_ticks() const { return identical_; }
  const Mismatch& mismatch() const { return mismatch_; }

 private:
  static bool fail(std::string* why, const std::string& msg) {
    *why = msg;
    return false;
  }

  std::FILE* file_ = nullptr;
  std::vector<unsigned char> record_, scratch_;  // one tick's input + output; the firmware's output
  std::size_t in_bytes_ = 0, out_bytes_ = 0;
  long ticks_ = 0, next_ = 0, identical_ = 0;
  bool read_ok_ = true;
  Mismatch mismatch_;
};

}  // namespace firmware
