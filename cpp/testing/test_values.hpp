#pragma once
// Constants the C++ tests share, defined once (the sanitizer build compiles several test sources
// as one translation unit, where per-file copies collide).
#include <limits>

namespace kiloloop {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace kiloloop
