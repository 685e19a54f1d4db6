#pragma once
// The back-to-back log's record format: every field of a controller input or output (the lists
// in firmware/fields.hpp), in list order, as raw 8-byte words: doubles as they are in memory
// (bit patterns, never printed), integers, booleans, enums and Status as int64. Header-only and
// allocation-free, so the firmware replay uses it inside its loop.
//
// Log file: LogHeader, then per tick the input record followed by the output record.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include <Eigen/Core>

#include "kiloloop/firmware/fields.hpp"

namespace kiloloop {

enum class Family : std::int64_t { kArm = 1, kQuadruped = 2, kAerial = 3 };

struct LogHeader {
  char magic[8];                 // "KLB2B01" + NUL
  std::int64_t family;           // Family
  std::int64_t input_bytes;      // per tick
  std::int64_t output_bytes;     // per tick
};
inline constexpr char kLogMagic[8] = {'K', 'L', 'B', '2', 'B', '0', '1', '\0'};

namespace record_detail {

template <class T>
inline constexpr bool kWord = std::is_arithmetic_v<T> || std::is_enum_v<T>;

inline void put_word(unsigned char* p, double x) { std::memcpy(p, &x, 8); }
template <class T>
void put_word(unsigned char* p, T x) {
  const std::int64_t i = static_cast<std::int64_t>(x);
  std::memcpy(p, &i, 8);
}
inline void get_word(const unsigned char* p, double& x) { std::memcpy(&x, p, 8); }
template <class T>
void get_word(const unsigned char* p, T& x) {
  std::int64_t i = 0;
  std::memcpy(&i, p, 8);
  x = static_cast<T>(i);
}

}  // namespace record_detail

// Bytes of one record (sizes of dynamic vectors as they are now).
class RecordSize {
 public:
  template <class T>
  void operator()(const char*, const T& x) {
    if constexpr (record_detail::kWord<T>) bytes_ += 8;
    else bytes_ += 8 * static_cast<std::size_t>(x.size());
  }
  std::size_t bytes() const { return bytes_; }

 private:
  std::size_t bytes_ = 0;
};

// Writes a record into a buffer of RecordSize bytes.
class RecordWriter {
 public:
  explicit RecordWriter(unsigned char* out) : p_(out) {}
  template <class T>
  void operator()(const char*, const T& x) {
    if constexpr (record_detail::kWord<T>) {
      record_detail::put_word(p_, x);
      p_ += 8;
    } else {
      for (Eigen::Index k = 0; k < x.size(); ++k, p_ += 8) record_detail::put_word(p_, double(x.data()[k]));
    }
  }

 private:
  unsigned char* p_;
};

// Reads a record into an object already sized like the writer's (make_input()).
class RecordReader {
 public:
  explicit RecordReader(const unsigned char* in) : p_(in) {}
  template <class T>
  void operator()(const char*, T& x) {
    if constexpr (record_detail::kWord<T>) {
      record_detail::get_word(p_, x);
      p_ += 8;
    } else {
      for (Eigen::Index k = 0; k < x.size(); ++k, p_ += 8) record_detail::get_word(p_, x.data()[k]);
    }
  }

 private:
  const unsigned char* p_;
};

// The field holding byte `offset` of a record, and the element index inside it.
class FieldAt {
 public:
  explicit FieldAt(std::size_t offset) : offset_(offset) {}
  template <class T>
  void operator()(const char* name, const T& x) {
    std::size_t bytes = 8;
    if constexpr (!record_detail::kWord<T>) bytes = 8 * static_cast<std::size_t>(x.size());
    if (name_ == nullptr && offset_ < start_ + bytes) {
      name_ = name;
      element_ = static_cast<int>((offset_ - start_) / 8);
    }
    start_ += bytes;
  }
  const char* name() const { return name_ ? name_ : "?"; }
  int element() const { return element_; }

 private:
  std::size_t offset_, start_ = 0;
  const char* name_ = nullptr;
  int element_ = 0;
};

template <class IO>
std::size_t record_bytes(const IO& io) {
  RecordSize size;
  visit_fields(const_cast<IO&>(io), size);
  return size.bytes();
}

template <class IO>
void write_record(const IO& io, unsigned char* out) {
  visit_fields(const_cast<IO&>(io), RecordWriter(out));
}

template <class IO>
void read_record(const unsigned char* in, IO& io) {
  visit_fields(io, RecordReader(in));
}

}  // namespace kiloloop
